//! What signs people in: sign-in codes (selector and Argon2id hash), sessions and API
//! tokens (SHA-256 hashes). Nothing here is ever stored in clear.

use super::courses::Role;
use super::db::{self, OptionalExtension, params};
use super::{Error, Member, Store};
use crate::courses::codes::{self, NewCode, TypedCode};
use jiff::Timestamp;
use serde::Serialize;
use ts_rs::TS;

/// A typed code whose selector names someone; its secret not checked yet.
pub struct FoundCode {
    pub member: Member,
    pub selector: String,
    secret: String,
    hash: String,
    once: bool,
    expires_at: Option<i64>,
}

/// What a found code turned out to be.
pub enum CodeCheck {
    /// The wrong secret, or expired, or a one-time code someone used meanwhile.
    Refused,
    /// The code of this person (a one-time code is used up by it).
    Valid(Member),
}

/// An API token as listed (never the token itself).
#[derive(Debug, Serialize, TS)]
pub struct TokenInfo {
    pub id: i64,
    pub course: String,
    pub role: Role,
    #[ts(as = "String")]
    pub created_at: Timestamp,
    pub revoked: bool,
}

impl Store {
    /// Stores a new code for a member. `once`: it ends at its first use; `expires_at`:
    /// it ends then. Their earlier codes end, and so do the sessions signed in with them:
    /// whoever had a lost code is signed out.
    pub fn add_code(
        &self,
        member: i64,
        code: &NewCode,
        once: bool,
        expires_at: Option<Timestamp>,
        now: Timestamp,
    ) -> Result<(), Error> {
        self.transaction(|transaction| {
            transaction.execute("DELETE FROM codes WHERE member = ?1", params![member])?;
            transaction.execute("DELETE FROM sessions WHERE member = ?1", params![member])?;
            transaction.execute(
                "INSERT INTO codes (selector, member, hash, once, expires_at, created_at)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
                params![
                    code.selector,
                    member,
                    code.hash,
                    once,
                    expires_at.map(|t| t.as_second()),
                    now.as_second()
                ],
            )?;
            Ok(())
        })
    }

    /// Finds whose a typed code is, by its selector (no secret is checked: the caller
    /// checks a decoy's for a selector of nobody's, `codes::spend_like_a_check`).
    pub fn find_code(&self, typed: TypedCode) -> Result<Option<FoundCode>, Error> {
        let TypedCode { selector, secret } = typed;
        let connection = self.connection();
        let row: Option<(i64, String, bool, Option<i64>)> = connection
            .query_row(
                "SELECT member, hash, once, expires_at FROM codes WHERE selector = ?1",
                [&selector],
                |row| Ok((row.get(0)?, row.get(1)?, row.get(2)?, row.get(3)?)),
            )
            .optional()?;
        let Some((member, hash, once, expires_at)) = row else {
            return Ok(None);
        };
        Ok(Some(FoundCode {
            member: Store::member_by_id(&connection, member)?,
            selector,
            secret,
            hash,
            once,
            expires_at,
        }))
    }

    /// Checks a found code's secret (the slow hash, without holding the database) and
    /// its expiry; a one-time code is then spent, and of two simultaneous uses only one
    /// gets in.
    pub fn use_code(&self, found: FoundCode, now: Timestamp) -> Result<CodeCheck, Error> {
        let expired = found.expires_at.is_some_and(|at| now.as_second() > at);
        if expired || !codes::secret_matches(&found.secret, &found.hash) {
            return Ok(CodeCheck::Refused);
        }
        if found.once {
            let spent = self.connection().execute(
                "DELETE FROM codes WHERE selector = ?1 AND hash = ?2",
                params![found.selector, found.hash],
            )?;
            if spent == 0 {
                return Ok(CodeCheck::Refused);
            }
        }
        Ok(CodeCheck::Valid(found.member))
    }

    /// Starts a session for a member until `expires_at`; returns the key for the cookie.
    pub fn start_session(
        &self,
        member: i64,
        now: Timestamp,
        expires_at: Timestamp,
    ) -> Result<String, Error> {
        let key = codes::new_token("");
        let connection = self.connection();
        connection.execute(
            "DELETE FROM sessions WHERE expires_at < ?1",
            [now.as_second()],
        )?;
        connection.execute(
            "INSERT INTO sessions (hash, member, created_at, expires_at) VALUES (?1, ?2, ?3, ?4)",
            params![
                codes::token_hash(&key),
                member,
                now.as_second(),
                expires_at.as_second()
            ],
        )?;
        Ok(key)
    }

    /// The member a session key belongs to, while the session lasts.
    pub fn session(&self, key: &str, now: Timestamp) -> Result<Option<Member>, Error> {
        let connection = self.connection();
        let member: Option<i64> = connection
            .query_row(
                "SELECT member FROM sessions WHERE hash = ?1 AND expires_at >= ?2",
                params![codes::token_hash(key), now.as_second()],
                |row| row.get(0),
            )
            .optional()?;
        Ok(member
            .map(|id| Store::member_by_id(&connection, id))
            .transpose()?)
    }

    pub fn end_session(&self, key: &str) -> Result<(), Error> {
        self.connection().execute(
            "DELETE FROM sessions WHERE hash = ?1",
            [codes::token_hash(key)],
        )?;
        Ok(())
    }

    /// A new API token for a course's staff role; returns its id and the token.
    pub fn create_token(
        &self,
        course: &str,
        role: Role,
        now: Timestamp,
    ) -> Result<(i64, String), Error> {
        if !role.is_staff() {
            return Err(Error::Conflict(
                "API tokens are for staff: --role instructor or --role assistant".into(),
            ));
        }
        let token = codes::new_token("estlab_");
        let connection = self.connection();
        Ok((
            connection.query_row(
                "INSERT INTO tokens (course, role, hash, created_at)
             VALUES (?1, ?2, ?3, ?4) RETURNING id",
                params![
                    course,
                    role.as_str(),
                    codes::token_hash(&token),
                    now.as_second()
                ],
                |row| row.get(0),
            )?,
            token,
        ))
    }

    /// The course and role an API token stands for, unless it was revoked.
    pub fn token(&self, token: &str) -> Result<Option<TokenInfo>, Error> {
        Ok(self
            .connection()
            .query_row(
                "SELECT id, course, role, created_at, revoked_at IS NOT NULL FROM tokens
                 WHERE hash = ?1 AND revoked_at IS NULL",
                [codes::token_hash(token)],
                token_info,
            )
            .optional()?)
    }

    pub fn tokens(&self, course: &str) -> Result<Vec<TokenInfo>, Error> {
        let connection = self.connection();
        let tokens = connection.query_map(
            "SELECT id, course, role, created_at, revoked_at IS NOT NULL FROM tokens
             WHERE course = ?1 ORDER BY id",
            params![course],
            token_info,
        )?;
        Ok(tokens)
    }

    /// Revokes a course's token; false when it has no token of that id.
    pub fn revoke_token(&self, course: &str, id: i64, now: Timestamp) -> Result<bool, Error> {
        let revoked = self.connection().execute(
            "UPDATE tokens SET revoked_at = COALESCE(revoked_at, ?3) WHERE course = ?1 AND id = ?2",
            params![course, id, now.as_second()],
        )?;
        Ok(revoked == 1)
    }
}

fn token_info(row: &db::Row) -> db::Result<TokenInfo> {
    Ok(TokenInfo {
        id: row.get(0)?,
        course: row.get(1)?,
        role: Role::parse(&row.get::<_, String>(2)?),
        created_at: Timestamp::from_second(row.get(3)?).unwrap_or(Timestamp::UNIX_EPOCH),
        revoked: row.get(4)?,
    })
}
