//! A round of peer review, from its opening to what its marks add up to: who takes part
//! (the course's students who have answered the set), the sheets frozen as they stand,
//! the hand-out (`review`), a late author joining, the sheets of a reviewer who left
//! going to others, the marks a reviewer may give, and each author's share of correct
//! marks with the bonus it earns. Staff act through a [`Setup`] (who, when, logged).

use super::questions::{self, QuestionSet};
use super::review;
use super::setup::{Error, Setup};
use crate::store::{self, Mark, Member, NewRound, Role, Round, SheetAnswer, Store};
use labs::Exercise;
use std::collections::{HashMap, HashSet};

/// The share of correct marks above which a student earns the bonus, unless the round
/// says otherwise: the lab's "more than 30 %".
pub const BONUS_ABOVE: f64 = 0.3;

/// The longest comment of a mark, in characters.
pub const MAX_COMMENT: usize = 2_000;

/// What staff give to open a round.
pub struct Opening {
    pub part: usize,
    pub per_sheet: usize,
    pub bonus_above: f64,
}

/// Whether `member` is a student of the roster (not dropped) who has answered a question
/// of `set`, the set `part` of the assignment.
pub fn may_take_part(
    store: &Store,
    member: &Member,
    lab: Exercise,
    (part, set): (usize, &QuestionSet),
) -> Result<bool, store::Error> {
    Ok(member.role == Role::Student
        && !member.dropped
        && !sheet(store, member, lab, part, set)?.is_empty())
}

/// `member`'s answers to the questions of `set` (the set `part`), in the set's order.
fn sheet(
    store: &Store,
    member: &Member,
    lab: Exercise,
    part: usize,
    set: &QuestionSet,
) -> Result<Vec<SheetAnswer>, store::Error> {
    let mut answers: Vec<SheetAnswer> = store
        .answers(member.id, lab)?
        .into_iter()
        .filter(|a| a.part == part)
        .map(|a| SheetAnswer {
            question: a.question,
            answer: a.answer,
        })
        .collect();
    let place = |id: &str| set.questions.iter().position(|q| q.id == id);
    answers.retain(|a| place(&a.question).is_some());
    answers.sort_by_key(|a| place(&a.question));
    Ok(answers)
}

/// The set a round reviews, as it was when the round opened.
pub fn set_of(round: &Round) -> Result<QuestionSet, store::Error> {
    questions::read(&round.questions)
        .map_err(|e| store::Error::Conflict(format!("the questions of round {}: {e}", round.id)))
}

fn random_seed() -> u64 {
    let mut bytes = [0u8; 8];
    getrandom::fill(&mut bytes).expect("the system's random source");
    u64::from_le_bytes(bytes)
}

/// Opens a round: every student who has answered the set takes part, their sheets as
/// they stand now; its id.
pub fn open(setup: &Setup, lab: Exercise, opening: &Opening) -> Result<i64, Error> {
    let store = setup.store;
    let sources = questions::sources(store, setup.course, lab)?;
    let Some(source) = sources.get(opening.part) else {
        return Err(Error::Invalid(format!(
            "part {}: the assignment has {} question sets, counted from 0",
            opening.part,
            sources.len()
        )));
    };
    let set = questions::read(source).map_err(Error::Invalid)?;
    if !(0.0..1.0).contains(&opening.bonus_above) {
        return Err(Error::Invalid(format!(
            "bonus_above {}: a share from 0 up to (not including) 1",
            opening.bonus_above
        )));
    }
    if let Some(open) = store
        .rounds(setup.course, lab)?
        .into_iter()
        .find(|r| r.part == opening.part && r.closed_at.is_none())
    {
        return Err(Error::Invalid(format!(
            "round {} of {:?} is still open: close it first",
            open.id, set.title
        )));
    }
    let mut authors = Vec::new();
    for member in store.members(setup.course)? {
        if may_take_part(store, &member, lab, (opening.part, &set))? {
            authors.push(member);
        }
    }
    let ids: Vec<i64> = authors.iter().map(|m| m.id).collect();
    let seed = random_seed();
    let pairs = review::hand_out(&ids, opening.per_sheet, seed).map_err(Error::Invalid)?;
    let sheets = authors
        .iter()
        .map(|m| Ok((m.id, sheet(store, m, lab, opening.part, &set)?)))
        .collect::<Result<Vec<_>, store::Error>>()?;
    let new = NewRound {
        course: setup.course,
        lab,
        part: opening.part,
        per_sheet: opening.per_sheet,
        bonus_above: opening.bonus_above,
        seed,
        questions: source,
        opened_by: setup.actor,
    };
    let id = store.open_round(&new, &sheets, &pairs, setup.now)?;
    setup.audit(
        "review",
        &format!(
            "{lab}: round {id} of {:?} opened, {} sheets, {} reviews each, bonus above {:.0} %",
            set.title,
            authors.len(),
            opening.per_sheet,
            opening.bonus_above * 100.0
        ),
    )?;
    Ok(id)
}

/// The round `id` of the assignment, open.
fn open_round(setup: &Setup, lab: Exercise, id: i64) -> Result<Round, Error> {
    let round = setup
        .store
        .round(setup.course, lab, id)?
        .ok_or_else(|| Error::Invalid(format!("{lab} has no review round {id}")))?;
    if round.closed_at.is_some() {
        return Err(Error::Invalid(format!("round {id} is closed")));
    }
    Ok(round)
}

/// Closes a round: each author then sees their marks.
pub fn close(setup: &Setup, lab: Exercise, id: i64) -> Result<(), Error> {
    open_round(setup, lab, id)?;
    setup.store.close_round(id, setup.now)?;
    setup.audit("review", &format!("{lab}: round {id} closed"))
}

/// A student who answered after the round opened joins it with their sheet as it stands.
pub fn join(setup: &Setup, lab: Exercise, id: i64, login: &str) -> Result<(), Error> {
    let store = setup.store;
    let round = open_round(setup, lab, id)?;
    let member = store.member(setup.course, login)?;
    let set = set_of(&round)?;
    if !may_take_part(store, &member, lab, (round.part, &set))? {
        return Err(Error::Invalid(format!(
            "{login} has not answered {:?} or is not on the roster: only its students who answered join",
            set.title
        )));
    }
    let answers = sheet(store, &member, lab, round.part, &set)?;
    let pairs = store.pairs(id)?;
    let done: HashSet<review::Pair> = pairs
        .iter()
        .filter(|p| p.submitted_at.is_some())
        .map(|p| p.pair)
        .collect();
    let all: Vec<review::Pair> = pairs.iter().map(|p| p.pair).collect();
    let (removed, added) = review::join(
        &all,
        &done,
        member.id,
        round.per_sheet,
        round.seed ^ member.id as u64,
    );
    if added.is_empty() {
        return Err(Error::Invalid(format!(
            "{login} takes part in round {id} already"
        )));
    }
    store.join_round(id, (member.id, &answers), &removed, &added)?;
    setup.audit("review", &format!("{lab}: {login} joined round {id}"))
}

/// The sheets a student who left had not reviewed go to others; how many moved, and how
/// many found nobody.
pub fn reassign(
    setup: &Setup,
    lab: Exercise,
    id: i64,
    login: &str,
) -> Result<(usize, usize), Error> {
    let store = setup.store;
    let round = open_round(setup, lab, id)?;
    let member = store.member(setup.course, login)?;
    let pairs = store.pairs(id)?;
    let done: HashSet<review::Pair> = pairs
        .iter()
        .filter(|p| p.submitted_at.is_some())
        .map(|p| p.pair)
        .collect();
    let all: Vec<review::Pair> = pairs.iter().map(|p| p.pair).collect();
    let moves = review::reassign(
        &all,
        &done,
        member.id,
        round.seed ^ member.id.rotate_left(17) as u64,
    );
    store.move_pairs(id, &moves)?;
    let moved = moves.iter().filter(|(_, new)| new.is_some()).count();
    let stranded = moves.len() - moved;
    setup.audit(
        "review",
        &format!("{lab}: {login}'s {moved} open sheets of round {id} went to others ({stranded} found nobody)"),
    )?;
    Ok((moved, stranded))
}

/// Checks a reviewer's marks of a sheet of `set`: each question at most once, known, its
/// comment within `MAX_COMMENT`; and, to submit, every question the sheet answers
/// marked.
pub fn check_marks(
    set: &QuestionSet,
    sheet: &[SheetAnswer],
    marks: &[Mark],
    submit: bool,
) -> Result<(), String> {
    let mut seen = HashSet::new();
    for mark in marks {
        if !sheet.iter().any(|a| a.question == mark.question) {
            return Err(format!(
                "{:?} is no question the sheet answers (of {:?})",
                mark.question, set.title
            ));
        }
        if !seen.insert(mark.question.as_str()) {
            return Err(format!("{} is marked twice", mark.question));
        }
        if mark.comment.chars().count() > MAX_COMMENT {
            return Err(format!(
                "the comment on {} is longer than {MAX_COMMENT} characters",
                mark.question
            ));
        }
    }
    if submit && let Some(missing) = sheet.iter().find(|a| !seen.contains(a.question.as_str())) {
        return Err(format!(
            "{} is not marked yet: mark every answer to submit",
            missing.question
        ));
    }
    Ok(())
}

/// What a student's marks add up to in a round.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, ts_rs::TS)]
pub struct Tally {
    /// Marks of submitted reviews of their sheet.
    #[ts(type = "number")]
    pub marks: usize,
    #[ts(type = "number")]
    pub correct: usize,
    /// `correct / marks`; none without marks.
    pub share: Option<f64>,
    /// Whether the share is above the round's threshold; none without marks.
    pub bonus: Option<bool>,
}

/// Each author's tally in a round, from the marks of submitted reviews.
pub fn tallies(store: &Store, round: &Round) -> Result<HashMap<i64, Tally>, store::Error> {
    let submitted: HashSet<review::Pair> = store
        .pairs(round.id)?
        .into_iter()
        .filter(|p| p.submitted_at.is_some())
        .map(|p| p.pair)
        .collect();
    let mut tallies: HashMap<i64, Tally> = HashMap::new();
    for (author, _) in store.sheets(round.id)? {
        tallies.insert(author, Tally::default());
    }
    for (pair, mark) in store.marks(round.id)? {
        if submitted.contains(&pair) {
            let tally = tallies.entry(pair.author).or_default();
            tally.marks += 1;
            tally.correct += usize::from(mark.correct);
        }
    }
    for tally in tallies.values_mut() {
        tally.share = (tally.marks > 0).then(|| tally.correct as f64 / tally.marks as f64);
        tally.bonus = tally.share.map(|share| share > round.bonus_above);
    }
    Ok(tallies)
}

/// What the review rounds of an assignment gave its students, for the gradebook: for
/// each question set with a closed round (by place, in order), each student's tally (by
/// id) in the latest round of it to close.
#[derive(Debug, Default)]
pub struct Reviewed {
    pub parts: Vec<(usize, HashMap<String, Tally>)>,
}

pub fn reviewed(store: &Store, course: &str, lab: Exercise) -> Result<Reviewed, store::Error> {
    let mut latest: HashMap<usize, Round> = HashMap::new();
    for round in store.rounds(course, lab)? {
        let Some(closed) = round.closed_at else {
            continue;
        };
        if latest
            .get(&round.part)
            .is_none_or(|r| r.closed_at < Some(closed))
        {
            latest.insert(round.part, round);
        }
    }
    let logins: HashMap<i64, String> = store
        .members(course)?
        .into_iter()
        .map(|m| (m.id, m.login))
        .collect();
    let mut parts = Vec::new();
    for (part, round) in latest {
        let tallies = tallies(store, &round)?
            .into_iter()
            .filter_map(|(id, tally)| Some((logins.get(&id)?.clone(), tally)))
            .collect();
        parts.push((part, tallies));
    }
    parts.sort_by_key(|(part, _)| *part);
    Ok(Reviewed { parts })
}
