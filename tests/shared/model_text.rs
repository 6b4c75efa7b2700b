//! The model texts inside Rust sources: the body of each `oscillator! { ... }`, as a
//! model file would hold it (shared by the `dsl` and `cli` test binaries).
#![allow(dead_code)]

/// The body of each `oscillator! { ... }` in `text`, with everything before it blanked
/// (newlines kept, other characters as spaces) so that lines and columns are the file's.
pub fn bodies(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(i) = text[from..].find("oscillator! {") {
        let open = from + i + "oscillator! ".len();
        let mut depth = 0;
        let mut close = None;
        for (j, ch) in text[open..].char_indices() {
            match ch {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        close = Some(open + j);
                        break;
                    }
                }
                _ => {}
            }
        }
        let close = close.expect("balanced braces");
        let blank: String =
            text[..=open].chars().map(|c| if c == '\n' { '\n' } else { ' ' }).collect();
        out.push(format!("{blank}{}", &text[open + 1..close]));
        from = close;
    }
    out
}
