//! An exercise's starter file in every language, made from one template (`web/starter.txt`
//! in its folder): the prose written once, the functions declared once. A line of the
//! template is
//!
//! - `#` and text: a comment, `// text` in JavaScript, `# text` in Python, `% text` in
//!   MATLAB;
//! - `def name(a, b) -> c, d`: a function the student writes, with its arguments and the
//!   names of what it returns (one name for a single value; MATLAB declares them, the
//!   harnesses of the other languages name a tuple's values with them), which throws "not
//!   implemented";
//! - `js|`, `py|` or `m|` and a line: that line in the one language only (a convention
//!   that differs, a function given whole);
//! - anything else (an empty line): itself.
//!
//! The rendered starters are committed beside the template (`web/starter.js`,
//! `web/starter.py`, `web/starter.m`: the workbench serves them, the end-to-end tests read
//! them), and a test holds them to what the template makes; `ESTLAB_WRITE_STARTERS=1 cargo
//! test -p labs starters` writes them anew.

use crate::Language;
use serde::Serialize;

/// A student function as the template declares it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Signature {
    pub name: &'static str,
    pub arguments: Vec<&'static str>,
    /// The names of what it returns: one for a single value, the contract's fields, in
    /// order, for several.
    pub outputs: Vec<&'static str>,
}

/// The template's marker of a line in one language only.
fn marker(language: Language) -> &'static str {
    match language {
        Language::JavaScript => "js",
        Language::Python => "py",
        Language::Matlab => "m",
    }
}

/// The starter in `language` that `template` makes.
pub fn render(template: &'static str, language: Language) -> String {
    let mut out = String::new();
    for line in template.lines() {
        let line = match line.split_once('|') {
            Some((only, rest)) if only == marker(language) => rest,
            Some(("js" | "py" | "m", _)) => continue,
            _ => line,
        };
        if let Some(text) = line.strip_prefix('#') {
            out += match language {
                Language::JavaScript => "//",
                Language::Python => "#",
                Language::Matlab => "%",
            };
            out += text;
        } else if let Some(Signature {
            name,
            arguments,
            outputs,
        }) = signature(line)
        {
            let args = arguments.join(", ");
            out += &match language {
                Language::JavaScript => format!(
                    "function {name}({args}) {{\n  throw new Error(\"{name}: not implemented\");\n}}"
                ),
                Language::Python => format!(
                    "def {name}({args}):\n    raise NotImplementedError(\"{name}: not implemented\")"
                ),
                Language::Matlab => {
                    let returns = match outputs.as_slice() {
                        [one] => (*one).to_owned(),
                        several => format!("[{}]", several.join(", ")),
                    };
                    format!(
                        "{}\n  error('{name}: not implemented');\nend",
                        matlab_declaration(&format!("function {returns} = {name}("), &arguments)
                    )
                }
            };
        } else {
            out += line;
        }
        out += "\n";
    }
    out
}

/// A MATLAB function's first line, `head` then the arguments, continued with `...` onto
/// indented lines where it would be wider than 80 columns.
fn matlab_declaration(head: &str, arguments: &[&str]) -> String {
    let mut out = head.to_owned();
    let mut width = head.len();
    for (at, argument) in arguments.iter().enumerate() {
        let last = at + 1 == arguments.len();
        let piece = format!("{argument}{}", if last { ")" } else { ", " });
        if width + piece.trim_end().len() > 76 && at > 0 {
            out = out.trim_end().to_owned() + " ...\n    ";
            width = 4;
        }
        width += piece.len();
        out += &piece;
    }
    if arguments.is_empty() {
        out += ")";
    }
    out
}

/// The student functions `template` declares, in its order.
pub fn signatures(template: &'static str) -> Vec<Signature> {
    template.lines().filter_map(signature).collect()
}

/// A stub line, `def name(a, b) -> c, d` (no colon: a line of Python given whole has one).
fn signature(line: &'static str) -> Option<Signature> {
    let (call, outputs) = line.strip_prefix("def ")?.split_once(" -> ")?;
    let (name, args) = call.strip_suffix(')')?.split_once('(')?;
    let names = |list: &'static str| -> Vec<&'static str> {
        list.split(',')
            .map(str::trim)
            .filter(|name| !name.is_empty())
            .collect()
    };
    let is_name = |name: &str| name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    let outputs = names(outputs);
    (is_name(name) && !outputs.is_empty() && outputs.iter().all(|o| is_name(o))).then(|| {
        Signature {
            name,
            arguments: names(args),
            outputs,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Exercise;
    use std::path::Path;

    #[test]
    fn a_template_renders_comments_stubs_and_each_languages_lines() {
        let template = "# Title\n#\njs|const A = 1;\npy|A = 1\nm|A = 1;\n\ndef f(x, y) -> a, b\n";
        assert_eq!(
            render(template, Language::JavaScript),
            "// Title\n//\nconst A = 1;\n\nfunction f(x, y) {\n  throw new Error(\"f: not implemented\");\n}\n"
        );
        assert_eq!(
            render(template, Language::Python),
            "# Title\n#\nA = 1\n\ndef f(x, y):\n    raise NotImplementedError(\"f: not implemented\")\n"
        );
        assert_eq!(
            render(template, Language::Matlab),
            "% Title\n%\nA = 1;\n\nfunction [a, b] = f(x, y)\n  error('f: not implemented');\nend\n"
        );
        assert_eq!(
            signatures(template),
            [Signature {
                name: "f",
                arguments: vec!["x", "y"],
                outputs: vec!["a", "b"],
            }]
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

    /// Every exercise's template declares each function of its contract, and names the
    /// outputs of one that returns several as the contract names its fields.
    #[test]
    fn templates_declare_the_contracts_functions_and_outputs() {
        for &exercise in Exercise::ALL {
            let declared = signatures(exercise.declaration().starter_template);
            let fields = exercise.output_fields();
            for function in exercise.functions() {
                let signature = declared
                    .iter()
                    .find(|s| s.name == *function)
                    .unwrap_or_else(|| panic!("{exercise}: {function} is not declared"));
                if let Some(fields) = fields.get(function) {
                    assert_eq!(&signature.outputs, fields, "{exercise}: {function}");
                } else {
                    assert_eq!(signature.outputs.len(), 1, "{exercise}: {function}");
                }
            }
        }
    }
}
