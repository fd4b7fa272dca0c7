"""What ``progress=`` accepts: ``None``, a callable ``progress(what, done, total)``, or a
tqdm bar (anything with tqdm's ``update``, ``reset``, ``n``, ``total`` and ``set_description_str``),
which then shows the task's name and its count."""

from __future__ import annotations

from typing import Any, Callable, Optional, Union

from .errors import ParameterError

#: ``progress(what, done, total)``; ``total`` is 0 when it is not known in advance.
Callback = Callable[[str, int, int], object]
#: What a ``progress=`` argument may be.
Progress = Union[None, Callback, Any]


def _is_bar(p: Any) -> bool:
    return all(hasattr(p, a) for a in ("update", "reset", "n", "total", "set_description_str"))


def callback(progress: Progress) -> Optional[Callback]:
    """The callback for ``progress``: itself if callable, a tqdm bar's adapter, or None.

    Raises:
        ParameterError: anything else.
    """
    if progress is None:
        return None
    if _is_bar(progress):
        return _Bar(progress)
    if callable(progress):
        return progress  # type: ignore[no-any-return]
    raise ParameterError(
        f"invalid progress: got {type(progress).__name__}; allowed: None, a callable "
        "progress(what, done, total), or a tqdm bar"
    )


class _Bar:
    """Reports to a tqdm bar: a new task resets it (with its total, None when unknown)
    and names it; each report moves it to the task's count."""

    def __init__(self, bar: Any) -> None:
        self.bar = bar
        self.what: Optional[str] = None

    def __call__(self, what: str, done: int, total: int) -> None:
        bar = self.bar
        if what != self.what:
            self.what = what
            bar.reset(total=total or None)
            bar.set_description_str(what, refresh=False)
        elif total and bar.total != total:
            bar.total = total
        bar.update(done - bar.n)
