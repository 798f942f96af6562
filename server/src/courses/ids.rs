//! What a student id may be, and how names and emails are kept readable. An id names the
//! student's row on the dashboard and in the gradebook, and their files in exports
//! (`ID.js`, `ID/results.json`) that are unpacked on Windows, macOS and Linux and read by
//! plagiarism checkers; so an id must read as what it is, differ from every other id of
//! the course in more than case or look, and be a file name on every system.
//!
//! Ids are normalised to NFKC, not only NFC: an id is an identifier to compare (as
//! Unicode's UAX #31 says of identifiers), not text to show, and NFKC also folds the
//! compatibility forms that look like plain letters and punctuation (fullwidth `ｕ１` is
//! `u1`, fullwidth `／` is `/`, `COM¹` is `COM1`), so that the rules below see them as
//! what they look like. Names and emails are normalised to NFC only: they are shown as
//! written, and NFC only makes the two ways of writing `é` one.

use std::collections::HashMap;
use unicode_normalization::UnicodeNormalization;
use unicode_security::general_security_profile::IdentifierType;
use unicode_security::{GeneralSecurityProfile, MixedScript};

/// At most this many characters, and `MAX_BYTES` bytes of UTF-8 (file names have 255).
const MAX_CHARS: usize = 100;
const MAX_BYTES: usize = 200;

/// Characters Windows refuses in a file name (macOS and Linux refuse `/`; their
/// fullwidth forms fold to these under NFKC).
const NOT_IN_FILE_NAMES: [char; 9] = ['<', '>', ':', '"', '/', '\\', '|', '?', '*'];

/// Names Windows keeps for devices, with any extension (`CON.js` is the console).
const DEVICES: [&str; 6] = ["CON", "PRN", "AUX", "NUL", "CONIN$", "CONOUT$"];
const NUMBERED_DEVICES: [&str; 2] = ["COM", "LPT"];

/// Unicode's Bidi_Control characters (PropList.txt, fixed since Unicode 6.3): they
/// reorder the text around them, so `u1\u{202e}sj.exe` shows as `u1exe.js`.
const BIDI_CONTROLS: [char; 12] = [
    '\u{061c}', '\u{200e}', '\u{200f}', '\u{202a}', '\u{202b}', '\u{202c}', '\u{202d}', '\u{202e}',
    '\u{2066}', '\u{2067}', '\u{2068}', '\u{2069}',
];

/// An id as it is kept: its NFKC form.
pub fn normalise(id: &str) -> String {
    id.nfkc().collect()
}

/// A name or email as it is kept: its NFC form.
pub fn normalise_text(text: &str) -> String {
    text.nfc().collect()
}

fn code_point(c: char) -> String {
    format!("U+{:04X}", u32::from(c))
}

/// What is wrong with an id (already normalised), to follow `the id "…"`; `None` when
/// it may be one.
pub fn problem(id: &str) -> Option<String> {
    if id.chars().count() > MAX_CHARS || id.len() > MAX_BYTES {
        return Some(format!(
            "is longer than {MAX_CHARS} characters ({MAX_BYTES} bytes of UTF-8)"
        ));
    }
    for c in id.chars() {
        if c.is_control()
            || c.is_whitespace()
            || c.identifier_type() == Some(IdentifierType::Default_Ignorable)
        {
            return Some(format!(
                "holds {}, a space, an invisible character (zero-width or text direction) or a control",
                code_point(c)
            ));
        }
        if NOT_IN_FILE_NAMES.contains(&c) {
            return Some(format!(
                "holds {c:?}: an id names the student's files in exports, and none of < > : \" / \\ | ? * (nor their fullwidth forms) may be in a file name"
            ));
        }
        if !(c.identifier_allowed() || c == '@') {
            return Some(format!(
                "holds {c:?} ({}): an id is letters, digits, marks and - . _ ' @ (Unicode's identifier characters)",
                code_point(c)
            ));
        }
    }
    if !id.is_single_script() {
        return Some(
            "mixes scripts (such as Latin letters with Cyrillic or Greek ones), as look-alikes of other ids do".into(),
        );
    }
    if id.starts_with(['.', '-']) {
        return Some(
            "starts with '.' or '-' (a hidden file, or an option to a command, as a file name)"
                .into(),
        );
    }
    if id.ends_with('.') {
        return Some("ends with '.', which Windows drops from file names".into());
    }
    let stem = id.split('.').next().unwrap_or(id).to_ascii_uppercase();
    let numbered = NUMBERED_DEVICES.iter().any(|prefix| {
        stem.strip_prefix(prefix)
            .is_some_and(|n| n.len() == 1 && n.as_bytes()[0].is_ascii_digit())
    });
    if DEVICES.contains(&stem.as_str()) || numbered {
        return Some(format!(
            "is {stem}, which Windows keeps for a device (CON, PRN, AUX, NUL, COM0-9, LPT0-9), with any extension"
        ));
    }
    None
}

/// Whether an id (as stored, perhaps by an earlier release) can name its files as it is.
pub fn is_safe(id: &str) -> bool {
    !id.is_empty() && normalise(id) == id && problem(id).is_none()
}

/// What two ids that differ only in case share. Upper then lower case, so that the case
/// rules of every file system (NTFS's upcase table, APFS's folding) meet in one form:
/// `ı`, `I` and `i` are one here, and so are `ß` and `SS`.
pub fn fold(id: &str) -> String {
    normalise(&normalise(id).to_uppercase().to_lowercase())
}

/// What two ids that look alike share: the skeleton of Unicode's TR39 (`а`, Cyrillic, and
/// `a` are one) of the case-folded id.
pub fn look_alike(id: &str) -> String {
    unicode_security::skeleton(&fold(id)).collect()
}

/// The ids of a course (or a roster) seen so far, to find one a new id is too alike:
/// one it differs from only in case, or one it looks like when either has a letter from
/// outside ASCII. Two ids of ASCII that differ in more than case are the university's own
/// (its `1` and `l`, `rn` and `m` are different ids), and refusing them would refuse a
/// real roster; a look-alike needs a letter from elsewhere. `T` says where each was seen.
pub struct Alike<T> {
    folds: HashMap<String, (String, T)>,
    looks: HashMap<String, Vec<(String, T)>>,
}

impl<T> Default for Alike<T> {
    fn default() -> Alike<T> {
        Alike {
            folds: HashMap::new(),
            looks: HashMap::new(),
        }
    }
}

impl<T: Clone> Alike<T> {
    /// An id seen before that `id` is too alike, and where it was seen.
    pub fn find(&self, id: &str) -> Option<(&str, &T)> {
        if let Some((other, at)) = self.folds.get(&fold(id)) {
            return Some((other, at));
        }
        self.looks
            .get(&look_alike(id))?
            .iter()
            .find(|(other, _)| !(other.is_ascii() && id.is_ascii()))
            .map(|(other, at)| (other.as_str(), at))
    }

    pub fn insert(&mut self, id: &str, at: T) {
        self.folds
            .entry(fold(id))
            .or_insert_with(|| (id.to_string(), at.clone()));
        self.looks
            .entry(look_alike(id))
            .or_default()
            .push((id.to_string(), at));
    }
}

/// An id as the command line prints it: as it is when every character shows as itself,
/// else quoted with its invisible characters escaped (`"u1\u{202e}sj.exe"`), so that a
/// stored id from before these rules cannot reorder or hide what is printed around it.
pub fn shown(id: &str) -> String {
    let quoted = format!("{id:?}");
    if quoted[1..quoted.len() - 1] == *id {
        id.to_string()
    } else {
        quoted
    }
}

/// What is wrong with a name or an email (already normalised), to follow `the name "…"`.
/// Letters of any script and joiners are fine (Persian names need the zero-width
/// non-joiner); controls, line breaks and text-direction characters are not.
pub fn text_problem(text: &str) -> Option<String> {
    text.chars()
        .find(|&c| {
            c.is_control() || matches!(c, '\u{2028}' | '\u{2029}') || BIDI_CONTROLS.contains(&c)
        })
        .map(|c| {
            format!(
                "holds {}, a control, a line break or a text-direction character",
                code_point(c)
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_folded_to_nfkc_and_refused_when_unsafe_as_file_names() {
        assert_eq!(normalise("ｕ１"), "u1");
        assert_eq!(normalise("a／b"), "a/b");
        assert_eq!(normalise_text("Jose\u{301}"), "José");
        for ok in [
            "u1",
            "ada.lovelace",
            "ada@kth.se",
            "o'brien",
            "josé",
            "山田太郎",
            "u_1-2",
        ] {
            assert_eq!(problem(ok), None, "{ok}");
            assert!(is_safe(ok), "{ok}");
        }
        for (bad, says) in [
            ("a\u{200b}b", "U+200B"),
            ("u1\u{202e}sj.exe", "U+202E"),
            ("a b", "U+0020"),
            ("a<b", "'<'"),
            (&normalise("a＊b"), "'*'"),
            ("a:b", "':'"),
            ("a∕b", "U+2215"),
            ("a~b", "U+007E"),
            ("аlice", "mixes scripts"),
            (".x", "starts with"),
            ("-x", "starts with"),
            ("x.", "ends with"),
            ("CON", "CON"),
            ("con.js", "CON"),
            ("Lpt9", "LPT9"),
            (&normalise("COM¹"), "COM1"),
            (&"x".repeat(101), "longer"),
        ] {
            let problem = problem(bad).unwrap_or_else(|| panic!("{bad:?} passed"));
            assert!(problem.contains(says), "{bad:?}: {problem}");
        }
        assert!(problem("CONSOLE").is_none() && problem("COM10").is_none());
        assert!(!is_safe("Jose\u{301}"), "not in NFKC");
    }

    #[test]
    fn ids_collide_by_case_and_by_look_but_distinct_ascii_ids_do_not() {
        let mut seen = Alike::default();
        for (line, id) in [(2, "alice"), (3, "u1"), (4, "arnold"), (5, "ace")] {
            assert_eq!(seen.find(id), None, "{id}");
            seen.insert(id, line);
        }
        assert_eq!(seen.find("ALICE"), Some(("alice", &2)));
        assert_eq!(seen.find("\u{430}lice"), Some(("alice", &2)), "Cyrillic a");
        assert_eq!(
            seen.find("\u{430}\u{441}\u{435}"),
            Some(("ace", &5)),
            "all Cyrillic"
        );
        assert_eq!(seen.find("ul"), None, "ASCII ids are the university's own");
        assert_eq!(seen.find("amold"), None);
        assert_eq!(seen.find("bob"), None);
        assert_eq!(fold("STRASSE"), fold("straße"));
        assert_eq!(fold("ID"), fold("ıd"));
    }

    #[test]
    fn an_id_with_invisible_characters_is_printed_escaped() {
        assert_eq!(shown("u1"), "u1");
        assert_eq!(shown("josé"), "josé");
        assert_eq!(shown("u1\u{202e}sj.exe"), "\"u1\\u{202e}sj.exe\"");
    }

    #[test]
    fn names_may_hold_any_letters_but_no_controls_or_direction_marks() {
        assert_eq!(text_problem("Ada Lovelace"), None);
        assert_eq!(text_problem("\u{645}\u{6cc}\u{200c}\u{646}\u{627}"), None);
        assert!(text_problem("Ada\u{202e}").unwrap().contains("U+202E"));
        assert!(text_problem("Ada\nx").unwrap().contains("U+000A"));
        assert!(text_problem("a\u{2028}b").is_some());
    }
}
