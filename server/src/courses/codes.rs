//! Sign-in codes, session keys and API tokens: made from the system's random source,
//! handed out once, and kept only as hashes.
//!
//! A sign-in code reads `ABCD-EFGH-JKMN-PQRS-TVWX-YZ01` (Crockford's base32, 120 bits):
//! its first 8 characters select its row (stored as they are), the 16 after them are
//! the secret (80 bits), kept as an Argon2id hash. A person types it, so it forgives
//! case, spaces, dashes and the letters O, I and L for 0, 1 and 1. Session keys and API
//! tokens are 256 random bits no person types: a SHA-256 hash is enough for them, and
//! lets every request find its session with one lookup.

use argon2::Argon2;
use argon2::password_hash::phc::PasswordHash;
use argon2::password_hash::{PasswordHasher, PasswordVerifier};
use sha2::{Digest, Sha256};
use std::sync::LazyLock;

/// Crockford's base32: digits and letters without I, L, O and U.
const ALPHABET: &[u8; 32] = b"0123456789ABCDEFGHJKMNPQRSTVWXYZ";
const SELECTOR_CHARS: usize = 8;
const SECRET_CHARS: usize = 16;

/// A code as handed out: the text shown once, and what is stored of it.
pub struct NewCode {
    /// `ABCD-EFGH-...`, for the person.
    pub text: String,
    pub selector: String,
    /// The Argon2id hash of the secret part, as a PHC string.
    pub hash: String,
}

/// A typed code, split into its parts (upper case, without separators).
#[derive(Debug, PartialEq, Eq)]
pub struct TypedCode {
    pub selector: String,
    pub secret: String,
}

fn random_chars(n: usize) -> String {
    let mut bytes = vec![0u8; n];
    getrandom::fill(&mut bytes).expect("the system's random source");
    // 256 is a multiple of 32: every character is equally likely.
    bytes
        .iter()
        .map(|b| ALPHABET[usize::from(b % 32)] as char)
        .collect()
}

/// A new sign-in code.
pub fn new_code() -> NewCode {
    let selector = random_chars(SELECTOR_CHARS);
    let secret = random_chars(SECRET_CHARS);
    let all = format!("{selector}{secret}");
    let text = all
        .as_bytes()
        .chunks(4)
        .map(|group| std::str::from_utf8(group).expect("ASCII"))
        .collect::<Vec<_>>()
        .join("-");
    NewCode {
        text,
        hash: hash_secret(&secret),
        selector,
    }
}

fn hash_secret(secret: &str) -> String {
    Argon2::default()
        .hash_password(secret.as_bytes())
        .expect("Argon2 with its default parameters hashes any input")
        .to_string()
}

/// Reads a code as a person typed or pasted it; `None` when it cannot be one.
pub fn read_code(typed: &str) -> Option<TypedCode> {
    let chars: String = typed
        .chars()
        .filter(|c| !c.is_whitespace() && *c != '-')
        .map(|c| match c.to_ascii_uppercase() {
            'O' => '0',
            'I' | 'L' => '1',
            other => other,
        })
        .collect();
    let valid = chars.len() == SELECTOR_CHARS + SECRET_CHARS
        && chars.bytes().all(|b| ALPHABET.contains(&b));
    valid.then(|| TypedCode {
        selector: chars[..SELECTOR_CHARS].to_string(),
        secret: chars[SELECTOR_CHARS..].to_string(),
    })
}

/// Whether `secret` is the one hashed in `hash`.
pub fn secret_matches(secret: &str, hash: &str) -> bool {
    PasswordHash::new(hash).is_ok_and(|parsed| {
        Argon2::default()
            .verify_password(secret.as_bytes(), &parsed)
            .is_ok()
    })
}

/// A hash of a secret nobody has, checked when a code's selector matches nothing, so that
/// a wrong selector takes as long to refuse as a wrong secret.
static DECOY: LazyLock<String> = LazyLock::new(|| hash_secret(&random_chars(SECRET_CHARS)));

pub fn spend_like_a_check(secret: &str) {
    let _ = secret_matches(secret, &DECOY);
}

/// A session key or an API token (with `prefix`): 256 random bits in hexadecimal.
pub fn new_token(prefix: &str) -> String {
    let mut bytes = [0u8; 32];
    getrandom::fill(&mut bytes).expect("the system's random source");
    format!("{prefix}{}", hex(&bytes))
}

/// What is stored of a session key or an API token.
pub fn token_hash(token: &str) -> String {
    hex(&Sha256::digest(token.as_bytes()))
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_code_reads_back_however_it_is_typed_and_only_its_secret_matches() {
        let code = new_code();
        assert_eq!(code.text.len(), 24 + 5);
        assert!(!code.hash.contains(&code.text[10..]));
        let typed = read_code(&code.text.to_lowercase().replace('-', " ")).unwrap();
        assert_eq!(typed.selector, code.selector);
        assert!(secret_matches(&typed.secret, &code.hash));
        let other = new_code();
        let wrong = read_code(&other.text).unwrap();
        assert!(!secret_matches(&wrong.secret, &code.hash));
        assert!(!secret_matches(&typed.secret, "not a hash"));
        assert_eq!(
            read_code("OIL0-0000-0000-0000-0000-0000").unwrap().selector,
            "01100000"
        );
        assert_eq!(read_code("too short"), None);
        assert_eq!(read_code("UUUU-0000-0000-0000-0000-0000"), None);
    }

    #[test]
    fn tokens_are_long_random_and_stored_as_hashes() {
        let a = new_token("estlab_");
        let b = new_token("estlab_");
        assert_ne!(a, b);
        assert_eq!(a.len(), 7 + 64);
        assert_eq!(token_hash(&a).len(), 64);
        assert_ne!(token_hash(&a), token_hash(&b));
        assert!(!token_hash(&a).contains(&a[7..]));
    }
}
