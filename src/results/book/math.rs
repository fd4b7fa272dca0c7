//! LaTeX in the chapters (`$…$`, `$$…$$`) to MathML at build time, so the book renders
//! math offline without a script.

use anyhow::{bail, Result};
use mdbook_preprocessor::book::{Book, BookItem};
use mdbook_preprocessor::{Preprocessor, PreprocessorContext};
use pulldown_latex::config::DisplayMode;
use pulldown_latex::{push_mathml, Parser, RenderConfig, Storage};

/// Converts `$…$` (inline) and `$$…$$` (display) to MathML, outside code.
pub struct MathPreprocessor;

impl Preprocessor for MathPreprocessor {
    fn name(&self) -> &str {
        "mathml"
    }

    fn run(
        &self,
        _: &PreprocessorContext,
        mut book: Book,
    ) -> mdbook_preprocessor::errors::Result<Book> {
        let mut failure = None;
        book.for_each_mut(|item| {
            if let BookItem::Chapter(ch) = item {
                match convert_math(&ch.content) {
                    Ok(c) => ch.content = c,
                    Err(e) => {
                        failure.get_or_insert(anyhow::anyhow!("chapter '{}': {e}", ch.name));
                    }
                }
            }
        });
        match failure {
            Some(e) => Err(e),
            None => Ok(book),
        }
    }
}

/// One LaTeX fragment to MathML; parse errors are errors (the book must not ship them).
///
/// # Errors
/// When `tex` does not parse as LaTeX or its MathML cannot be written.
pub fn latex_to_mathml(tex: &str, display: bool) -> Result<String> {
    let storage = Storage::new();
    let events: Vec<_> = Parser::new(tex, &storage).collect();
    if let Some(Err(e)) = events.iter().find(|e| e.is_err()) {
        bail!("cannot parse LaTeX `{tex}`: {e}");
    }
    let config = RenderConfig {
        display_mode: if display {
            DisplayMode::Block
        } else {
            DisplayMode::Inline
        },
        ..Default::default()
    };
    let mut out = String::new();
    push_mathml(&mut out, events.into_iter(), config)?;
    // The MathML sits inside markdown: hide characters markdown would act on, and repair
    // pulldown-latex 0.8's `stretchy="true"minsize=…` (no space between attributes after
    // \bigl and friends), which markdown would not recognise as a tag.
    let mut safe = String::with_capacity(out.len());
    let chars: Vec<char> = out.chars().collect();
    for (i, &c) in chars.iter().enumerate() {
        let closing_quote = c == '"' && i > 0 && chars[i - 1] != '=';
        if closing_quote && chars.get(i + 1).is_some_and(|n| n.is_ascii_alphabetic()) {
            safe.push_str("\" ");
            continue;
        }
        match c {
            '*' | '_' | '\\' | '`' | '[' | ']' | '$' | '~' | '|' | '\n' => {
                if c != '\n' {
                    safe.push_str(&format!("&#{};", c as u32));
                }
            }
            c => safe.push(c),
        }
    }
    Ok(safe)
}

/// The subscripted symbols of a LaTeX fragment (`k_2`, `r_E`, `r_{E}`: one Latin letter
/// with a subscript of letters or digits) as a reader types them into the book's search —
/// `k2 k_2 k₂`, `rE r_E` — in a span the page does not show (class `search-terms`): the
/// search index is made from the text of the page, where MathML spells `k_2` as "k 2".
/// Empty when the fragment has none.
pub fn search_terms(tex: &str) -> String {
    const DIGITS: [char; 10] = ['₀', '₁', '₂', '₃', '₄', '₅', '₆', '₇', '₈', '₉'];
    let chars: Vec<char> = tex.chars().collect();
    let mut terms: Vec<String> = Vec::new();
    for i in 0..chars.len() {
        let letter = chars[i];
        let starts = i == 0 || !(chars[i - 1].is_ascii_alphabetic() || chars[i - 1] == '\\');
        if !letter.is_ascii_alphabetic() || !starts || chars.get(i + 1) != Some(&'_') {
            continue;
        }
        let sub: String = match chars.get(i + 2) {
            Some('{') => chars[i + 3..].iter().take_while(|c| **c != '}').collect(),
            Some(c) => c.to_string(),
            None => continue,
        };
        if sub.is_empty() || sub.len() > 3 || !sub.chars().all(|c| c.is_ascii_alphanumeric()) {
            continue;
        }
        let mut spellings = vec![format!("{letter}{sub}"), format!("{letter}_{sub}")];
        if sub.chars().all(|c| c.is_ascii_digit()) {
            let small: String = sub
                .chars()
                .filter_map(|c| c.to_digit(10).map(|d| DIGITS[d as usize]))
                .collect();
            spellings.push(format!("{letter}{small}"));
        }
        for s in spellings {
            if !terms.contains(&s) {
                terms.push(s);
            }
        }
    }
    if terms.is_empty() {
        return String::new();
    }
    // (the underscore escaped, as in the MathML: markdown must not read it as emphasis)
    let text = terms.join(" ").replace('_', "&#95;");
    format!("<span class=\"search-terms\" aria-hidden=\"true\">{text}</span>")
}

/// Replaces math delimiters in markdown, leaving fenced code and inline code alone.
/// `\$` is a literal dollar sign. Math may continue across line breaks (prose is wrapped),
/// but not across a blank line.
///
/// # Errors
/// When math is left open at a blank line or at the end, or a fragment does not parse
/// ([`latex_to_mathml`]).
pub fn convert_math(markdown: &str) -> Result<String> {
    let mut out = String::with_capacity(markdown.len());
    let mut in_fence = false;
    // open math: its text so far, and whether it is display math
    let mut open: Option<(String, bool)> = None;
    for line in markdown.split_inclusive('\n') {
        if open.is_none() && line.trim_start().starts_with("```") {
            in_fence = !in_fence;
            out.push_str(line);
            continue;
        }
        if in_fence {
            out.push_str(line);
            continue;
        }
        if let Some((buf, _)) = &open {
            if line.trim().is_empty() {
                bail!("math left open at a blank line: ${}", buf.trim());
            }
        }
        let mut rest = line;
        while !rest.is_empty() {
            if let Some((buf, display)) = open.as_mut() {
                let delimiter = if *display { "$$" } else { "$" };
                match rest.find(delimiter) {
                    Some(end) => {
                        buf.push_str(&rest[..end]);
                        let tex = buf.split_whitespace().collect::<Vec<_>>().join(" ");
                        out.push_str(&latex_to_mathml(&tex, *display)?);
                        out.push_str(&search_terms(&tex));
                        rest = &rest[end + delimiter.len()..];
                        open = None;
                    }
                    None => {
                        buf.push_str(rest);
                        rest = "";
                    }
                }
                continue;
            }
            let Some(pos) = rest.find(['$', '`', '\\']) else {
                out.push_str(rest);
                break;
            };
            out.push_str(&rest[..pos]);
            let tail = &rest[pos..];
            if let Some(after) = tail.strip_prefix("\\$") {
                out.push('$');
                rest = after;
            } else if let Some(after) = tail.strip_prefix('\\') {
                out.push('\\');
                rest = after;
            } else if let Some(code) = tail.strip_prefix('`') {
                let end = code.find('`').map_or(tail.len(), |e| e + 2);
                out.push_str(&tail[..end]);
                rest = &tail[end..];
            } else if let Some(after) = tail.strip_prefix("$$") {
                open = Some((String::new(), true));
                rest = after;
            } else {
                open = Some((String::new(), false));
                rest = &tail[1..];
            }
        }
    }
    if let Some((buf, _)) = open {
        bail!("unclosed math at the end of the chapter: ${}", buf.trim());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subscripted_symbols_are_spelled_for_the_search() {
        assert_eq!(
            search_terms("k = 100k_1, \\tilde r_{E} \\beta_1 x^2"),
            "<span class=\"search-terms\" aria-hidden=\"true\">k1 k&#95;1 k₁ rE r&#95;E</span>"
        );
        assert_eq!(search_terms("\\omega / (\\beta_1^-)^2"), "");
        let html = convert_math("the $r_E$ map").unwrap();
        assert!(
            html.contains("</math><span class=\"search-terms\""),
            "{html}"
        );
    }

    #[test]
    fn math_becomes_mathml_and_code_is_left_alone() {
        let md = "Let $k_j = (\\beta_j^-)^4$ and `$x$`.\n```\n$y$\n```\n$$\nK^+ = K^- + k\\mathbf{1}\\mathbf{1}^T\n$$\nCost \\$5.\n";
        let html = convert_math(md).unwrap();
        assert!(html.contains("<math"));
        assert!(html.contains("display=\"block\""));
        assert!(html.contains("`$x$`"));
        assert!(html.contains("\n$y$\n"));
        assert!(html.contains("Cost $5."));
        assert!(!html.contains("k_j"));
    }

    #[test]
    fn delimiter_sizes_give_well_formed_attributes() {
        let html = latex_to_mathml("\\bigl(x\\bigr)", false).unwrap();
        assert!(
            !html.contains("\"minsize") && !html.contains("\"maxsize"),
            "{html}"
        );
    }

    #[test]
    fn bad_latex_is_an_error() {
        assert!(convert_math("$\\frac{1}$").is_err());
        assert!(convert_math("$x").is_err());
        assert!(convert_math("$x\n\ny$").is_err(), "not across paragraphs");
    }

    #[test]
    fn inline_math_may_wrap_across_lines() {
        let html = convert_math("a sum $g(s) = x +\n y$ here\n").unwrap();
        assert!(html.contains("<math") && html.contains(" here"));
    }
}
