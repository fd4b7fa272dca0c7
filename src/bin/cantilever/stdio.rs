//! A closed standard output (`>&-`). Rust's runtime reopens a closed fd 0–2 on /dev/null
//! before `main`, so every print would then succeed into nothing and the run exit 0 with
//! its results lost. The runtime opens that /dev/null read-write, while a shell's
//! `> /dev/null` opens it write-only; so on Linux a read-write /dev/null on fd 1 is what a
//! closed stdout leaves (or the rare `1<> /dev/null`). Elsewhere nothing is detected.

/// Whether fd 1 is the runtime's stand-in for a closed standard output.
pub fn stdout_was_closed() -> bool {
    let target = std::fs::read_link("/proc/self/fd/1");
    if !target.is_ok_and(|t| t == std::path::Path::new("/dev/null")) {
        return false;
    }
    // "flags:\t0100002": octal open flags; the access mode is the low two bits
    let Ok(info) = std::fs::read_to_string("/proc/self/fdinfo/1") else {
        return false;
    };
    info.lines()
        .find_map(|l| l.strip_prefix("flags:"))
        .and_then(|f| u32::from_str_radix(f.trim(), 8).ok())
        .is_some_and(|flags| flags & 0o3 == 0o2)
}
