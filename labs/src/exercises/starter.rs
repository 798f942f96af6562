//! An exercise's starter file in every language, made from one template (`web/starter.txt`
//! in its folder): the prose written once, the functions declared once. A line of the
//! template is
//!
//! - `#` and text: a comment, `// text` in JavaScript, `# text` in Python;
//! - `def name(a, b)`: a function the student writes, which throws "not implemented";
//! - `js|` or `py|` and a line: that line in the one language only (a convention that
//!   differs, a function given whole);
//! - anything else (an empty line): itself.
//!
//! The rendered starters are committed beside the template (`web/starter.js`,
//! `web/starter.py`: the workbench serves them, the end-to-end tests read them), and a test
//! holds them to what the template makes; `ESTLAB_WRITE_STARTERS=1 cargo test -p labs
//! starters` writes them anew.

use crate::Language;

/// The starter in `language` that `template` makes.
pub fn render(template: &str, language: Language) -> String {
    let mut out = String::new();
    for line in template.lines() {
        let line = match (line.split_once('|'), language) {
            (Some(("js", rest)), Language::JavaScript) | (Some(("py", rest)), Language::Python) => {
                rest
            }
            (Some(("js" | "py", _)), _) => continue,
            _ => line,
        };
        if let Some(text) = line.strip_prefix('#') {
            out += match language {
                Language::JavaScript => "//",
                Language::Python => "#",
            };
            out += text;
        } else if let Some((name, args)) = stub(line) {
            out += &match language {
                Language::JavaScript => format!(
                    "function {name}({args}) {{\n  throw new Error(\"{name}: not implemented\");\n}}"
                ),
                Language::Python => format!(
                    "def {name}({args}):\n    raise NotImplementedError(\"{name}: not implemented\")"
                ),
            };
        } else {
            out += line;
        }
        out += "\n";
    }
    out
}

/// The name and arguments of a stub line, `def name(a, b)` (no colon: a line of Python
/// given whole has one).
fn stub(line: &str) -> Option<(&str, &str)> {
    let rest = line.strip_prefix("def ")?.strip_suffix(')')?;
    let (name, args) = rest.split_once('(')?;
    name.chars()
        .all(|c| c.is_ascii_alphanumeric() || c == '_')
        .then_some((name, args))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Exercise;
    use std::path::Path;

    #[test]
    fn a_template_renders_comments_stubs_and_each_languages_lines() {
        let template = "# Title\n#\njs|const A = 1;\npy|A = 1\n\ndef f(x, y)\n";
        assert_eq!(
            render(template, Language::JavaScript),
            "// Title\n//\nconst A = 1;\n\nfunction f(x, y) {\n  throw new Error(\"f: not implemented\");\n}\n"
        );
        assert_eq!(
            render(template, Language::Python),
            "# Title\n#\nA = 1\n\ndef f(x, y):\n    raise NotImplementedError(\"f: not implemented\")\n"
        );
    }

    /// Every exercise's committed starters are what its template makes, and each declares
    /// every student function, within 80 columns.
    #[test]
    fn starters_are_what_their_templates_make() {
        let write = std::env::var_os("ESTLAB_WRITE_STARTERS").is_some();
        let mut stale = Vec::new();
        for &exercise in Exercise::ALL {
            let folder = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("src/exercises")
                .join(exercise.folder())
                .join("web");
            let template = exercise.declaration().starter_template;
            for &language in Language::ALL {
                let made = render(template, language);
                let path = folder.join(format!("starter.{}", language.extension()));
                if write {
                    std::fs::write(&path, &made).unwrap();
                } else if exercise.declaration().starter(language) != made {
                    stale.push(path.display().to_string());
                }
                for line in made.lines() {
                    assert!(line.chars().count() <= 80, "{}: {line}", path.display());
                }
            }
        }
        assert!(
            stale.is_empty(),
            "not what their templates make (ESTLAB_WRITE_STARTERS=1 cargo test -p labs starters writes them): {}",
            stale.join(", ")
        );
    }
}
