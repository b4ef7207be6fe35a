//! The viewer page: `web/index.html` with `web/viewer.js` inlined, filled in for export or
//! live mode.

use std::io::Write;

use crate::error::is_unsafe_char;

const TEMPLATE: &str = include_str!("web/index.html");
const VIEWER: &str = include_str!("web/viewer.js");

/// Writes the page. `config` is `{"mode": "export" | "live", "summary": …}`; `scene` and
/// `samples` are base64 (empty in live mode, where the page fetches them).
pub fn write(
    w: &mut dyn Write,
    title: &str,
    config: &serde_json::Value,
    scene: &str,
    samples: &str,
) -> std::io::Result<()> {
    let config = script_safe_json(config);
    let title = html_escape(title);
    let mut rest = TEMPLATE;
    while let Some(at) = rest.find("{{") {
        w.write_all(&rest.as_bytes()[..at])?;
        let end = at + rest[at..].find("}}").expect("template placeholders are closed") + 2;
        let value = match &rest[at..end] {
            "{{TITLE}}" => title.as_str(),
            "{{CONFIG}}" => config.as_str(),
            "{{SCENE}}" => scene,
            "{{SAMPLES}}" => samples,
            "{{VIEWER}}" => VIEWER,
            other => panic!("unknown template placeholder {other}"),
        };
        w.write_all(value.as_bytes())?;
        rest = &rest[end..];
    }
    w.write_all(rest.as_bytes())
}

/// The page as a string (live mode serves it).
pub fn render(title: &str, config: &serde_json::Value) -> String {
    let mut out = Vec::new();
    write(&mut out, title, config, "", "").expect("writing to memory");
    String::from_utf8(out).expect("UTF-8 template")
}

/// JSON that can sit inside a `<script>` element: `<` is escaped so no `</script>` can occur,
/// and so is every character that must not appear raw in a text file (C1 controls, line
/// separators, bidirectional formatting: [`is_unsafe_char`]; JSON escapes the C0 controls).
fn script_safe_json(v: &serde_json::Value) -> String {
    let json = serde_json::to_string(v).expect("JSON of plain values");
    let mut out = String::with_capacity(json.len());
    for c in json.chars() {
        match c == '<' || is_unsafe_char(c) {
            true => out.push_str(&format!("\\u{:04x}", c as u32)),
            false => out.push(c),
        }
    }
    out
}

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn page_fills_every_placeholder_and_escapes() {
        let page = render("a<b", &serde_json::json!({"mode": "live", "x": "</script>"}));
        assert!(!page.contains("{{"), "all placeholders filled");
        assert!(page.contains("<title>a&lt;b</title>"));
        assert_eq!(page.matches("</script>").count(), 4, "only the page's own script ends");
        assert!(!VIEWER.contains("</script"), "the viewer can be inlined");
    }
}
