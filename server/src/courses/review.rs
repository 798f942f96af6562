//! Who reviews whose answer sheet in a round of peer review. A round hands each sheet to
//! `per_sheet` reviewers among the students who answered: never to its author, never
//! twice to the same reviewer, every sheet as often as every other and every reviewer as
//! many sheets, drawn from the round's seed so that the same round hands out the same
//! again. Students who answer after the round opened join it with every count kept
//! equal, and the sheets of a reviewer who left go to others, the busiest of whom then has
//! as few as can be.

use labs::rng::Rng;
use std::collections::{HashMap, HashSet};

/// A member of the course, as the store numbers them.
pub type Member = i64;

/// `reviewer` reviews the answer sheet of `author`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Pair {
    pub reviewer: Member,
    pub author: Member,
}

/// The most reviews of each sheet a round asks for.
pub const MAX_PER_SHEET: usize = 10;

/// The hand-out of a round among `authors` (each has answered; their order does not
/// matter): they are put in an order drawn from `seed`, `per_sheet` distinct shifts s
/// are drawn from 1 to n - 1, and the author in place i reviews the sheets in places
/// i + s (mod n). Each shift is a permutation without a fixed point, and distinct shifts
/// never pair the same two places twice: every sheet is reviewed `per_sheet` times,
/// every author reviews `per_sheet` sheets, none their own.
pub fn hand_out(authors: &[Member], per_sheet: usize, seed: u64) -> Result<Vec<Pair>, String> {
    let mut order: Vec<Member> = authors.to_vec();
    order.sort_unstable();
    order.dedup();
    let n = order.len();
    if !(1..=MAX_PER_SHEET).contains(&per_sheet) {
        return Err(format!(
            "reviews of each sheet: {per_sheet}; ask for 1 to {MAX_PER_SHEET}"
        ));
    }
    if n < 2 {
        return Err(format!(
            "{n} answer sheet{}: a review round needs two or more",
            if n == 1 { "" } else { "s" }
        ));
    }
    if per_sheet > n - 1 {
        return Err(format!(
            "{per_sheet} reviews of each sheet among {n} students: each can review at most {} sheets other than their own",
            n - 1
        ));
    }
    let mut rng = Rng::new(seed);
    rng.shuffle(&mut order);
    let mut shifts: Vec<usize> = (1..n).collect();
    rng.shuffle(&mut shifts);
    Ok(shifts[..per_sheet]
        .iter()
        .flat_map(|&shift| {
            let order = &order;
            (0..n).map(move |i| Pair {
                reviewer: order[i],
                author: order[(i + shift) % n],
            })
        })
        .collect())
}

/// How many sheets each reviewer has, and how many reviews each sheet, in `pairs`.
fn loads(pairs: &[Pair]) -> (HashMap<Member, usize>, HashMap<Member, usize>) {
    let mut reviewing = HashMap::new();
    let mut reviewed = HashMap::new();
    for pair in pairs {
        *reviewing.entry(pair.reviewer).or_insert(0) += 1;
        *reviewed.entry(pair.author).or_insert(0) += 1;
    }
    (reviewing, reviewed)
}

/// The `count` members of `candidates` with the least `load`, ties drawn by `rng`.
fn least_loaded(
    candidates: impl Iterator<Item = Member>,
    load: &HashMap<Member, usize>,
    count: usize,
    rng: &mut Rng,
) -> Vec<Member> {
    let mut candidates: Vec<Member> = candidates.collect();
    candidates.sort_unstable();
    rng.shuffle(&mut candidates);
    // A stable sort keeps the drawn order among equals.
    candidates.sort_by_key(|m| load.get(m).copied().unwrap_or(0));
    candidates.truncate(count);
    candidates
}

/// How the hand-out changes when `newcomer` answers after the round handed out `pairs`:
/// `per_sheet` pairs r -> a not yet reviewed (not in `done`), with distinct reviewers and
/// distinct authors, drawn from `seed`, each become r -> newcomer and newcomer -> a. Every
/// reviewer keeps their count of sheets and every sheet its count of reviews, and the
/// newcomer's sheet is reviewed, and they review, as often as everyone. Where too few
/// such pairs are left (a round nearly done), the newcomer's sheet goes to the others
/// with the fewest sheets, and the sheets with the fewest reviews to the newcomer, for the
/// rest. The pairs removed, then the pairs added; nothing if the newcomer is in the round.
pub fn join(
    pairs: &[Pair],
    done: &HashSet<Pair>,
    newcomer: Member,
    per_sheet: usize,
    seed: u64,
) -> (Vec<Pair>, Vec<Pair>) {
    if pairs
        .iter()
        .any(|p| p.author == newcomer || p.reviewer == newcomer)
    {
        return (Vec::new(), Vec::new());
    }
    let mut rng = Rng::new(seed);
    let mut open: Vec<Pair> = pairs
        .iter()
        .filter(|p| !done.contains(p))
        .copied()
        .collect();
    open.sort_unstable();
    rng.shuffle(&mut open);
    let (mut reviewers, mut authors) = (HashSet::new(), HashSet::new());
    let mut removed = Vec::new();
    for pair in open {
        if removed.len() == per_sheet {
            break;
        }
        if !reviewers.contains(&pair.reviewer) && !authors.contains(&pair.author) {
            reviewers.insert(pair.reviewer);
            authors.insert(pair.author);
            removed.push(pair);
        }
    }
    // The rest, if any, by the loads of what stays.
    let kept: Vec<Pair> = pairs
        .iter()
        .filter(|p| !removed.contains(p))
        .copied()
        .collect();
    let participants: Vec<Member> = pairs
        .iter()
        .flat_map(|p| [p.reviewer, p.author])
        .collect::<HashSet<_>>()
        .into_iter()
        .collect();
    let missing = per_sheet - removed.len();
    let (reviewing, reviewed) = loads(&kept);
    let more_reviewers = least_loaded(
        participants
            .iter()
            .copied()
            .filter(|m| !reviewers.contains(m)),
        &reviewing,
        missing,
        &mut rng,
    );
    let more_authors = least_loaded(
        participants
            .iter()
            .copied()
            .filter(|m| !authors.contains(m)),
        &reviewed,
        missing,
        &mut rng,
    );
    let added: Vec<Pair> = removed
        .iter()
        .map(|p| p.reviewer)
        .chain(more_reviewers)
        .map(|reviewer| Pair {
            reviewer,
            author: newcomer,
        })
        .chain(
            removed
                .iter()
                .map(|p| p.author)
                .chain(more_authors)
                .map(|author| Pair {
                    reviewer: newcomer,
                    author,
                }),
        )
        .collect();
    (removed, added)
}

/// Where the sheets `leaver` had not yet reviewed go: each such pair of `pairs` (not in
/// `done`) to a new reviewer among the others of the round, not the sheet's author nor one
/// who already has it, so that the most sheets any of them then has is as few as it can
/// be (the least bound L for which every sheet finds a place, each reviewer r taking at
/// most L - load(r) of them: a matching found by augmenting paths, candidates tried in an
/// order drawn from `seed`); `None` for a sheet nobody can take.
pub fn reassign(
    pairs: &[Pair],
    done: &HashSet<Pair>,
    leaver: Member,
    seed: u64,
) -> Vec<(Pair, Option<Pair>)> {
    let leaving: Vec<Pair> = pairs
        .iter()
        .filter(|p| p.reviewer == leaver && !done.contains(p))
        .copied()
        .collect();
    let staying: Vec<Pair> = pairs
        .iter()
        .filter(|p| !leaving.contains(p))
        .copied()
        .collect();
    let mut others: Vec<Member> = pairs
        .iter()
        .flat_map(|p| [p.reviewer, p.author])
        .filter(|&m| m != leaver)
        .collect::<HashSet<_>>()
        .into_iter()
        .collect();
    others.sort_unstable();
    let mut rng = Rng::new(seed);
    rng.shuffle(&mut others);
    let (load, _) = loads(&staying);
    let load = |m: &Member| load.get(m).copied().unwrap_or(0);
    // For each leaving sheet, who may take it.
    let eligible: Vec<Vec<Member>> = leaving
        .iter()
        .map(|old| {
            others
                .iter()
                .copied()
                .filter(|&m| {
                    m != old.author
                        && !staying.contains(&Pair {
                            reviewer: m,
                            author: old.author,
                        })
                })
                .collect()
        })
        .collect();
    let lowest = others.iter().map(load).min().unwrap_or(0);
    let highest = others.iter().map(load).max().unwrap_or(0) + leaving.len();
    // The least bound under which the most sheets find a place.
    let mut best: Vec<Option<Member>> = vec![None; leaving.len()];
    for bound in lowest..=highest {
        let taken = place(&eligible, |m| bound.saturating_sub(load(m)));
        let placed = taken.iter().filter(|t| t.is_some()).count();
        if placed > best.iter().filter(|t| t.is_some()).count() {
            best = taken;
        }
        if placed == leaving.len() {
            break;
        }
    }
    leaving
        .into_iter()
        .zip(best)
        .map(|(old, reviewer)| {
            let new = reviewer.map(|reviewer| Pair {
                reviewer,
                author: old.author,
            });
            (old, new)
        })
        .collect()
}

/// A most-sheets matching of sheet i to one of `eligible[i]`, reviewer m taking at most
/// `room(m)` sheets (Kuhn's augmenting paths); the reviewer of each sheet, if any.
fn place(eligible: &[Vec<Member>], room: impl Fn(&Member) -> usize) -> Vec<Option<Member>> {
    fn augment(
        sheet: usize,
        eligible: &[Vec<Member>],
        room: &dyn Fn(&Member) -> usize,
        taken: &mut Vec<Option<Member>>,
        seen: &mut HashSet<Member>,
    ) -> bool {
        for &m in &eligible[sheet] {
            if !seen.insert(m) {
                continue;
            }
            let holders: Vec<usize> = (0..taken.len()).filter(|&j| taken[j] == Some(m)).collect();
            if holders.len() < room(&m) {
                taken[sheet] = Some(m);
                return true;
            }
            for j in holders {
                if augment(j, eligible, room, taken, seen) {
                    taken[sheet] = Some(m);
                    return true;
                }
            }
        }
        false
    }
    let mut taken = vec![None; eligible.len()];
    for sheet in 0..eligible.len() {
        augment(sheet, eligible, &room, &mut taken, &mut HashSet::new());
    }
    taken
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Nobody has their own sheet or a sheet twice; the reviews of each sheet and the
    /// sheets of each reviewer are each within one of the others'.
    fn fair(pairs: &[Pair]) -> Result<(), String> {
        let distinct: HashSet<Pair> = pairs.iter().copied().collect();
        if distinct.len() != pairs.len() {
            return Err("a reviewer has a sheet twice".into());
        }
        if let Some(own) = pairs.iter().find(|p| p.reviewer == p.author) {
            return Err(format!("{own:?} reviews their own sheet"));
        }
        let (reviewing, reviewed) = loads(pairs);
        for (what, load) in [
            ("sheets of a reviewer", reviewing),
            ("reviews of a sheet", reviewed),
        ] {
            let (least, most) = (load.values().min(), load.values().max());
            if let (Some(least), Some(most)) = (least, most)
                && most - least > 1
            {
                return Err(format!("{what}: from {least} to {most}"));
            }
        }
        Ok(())
    }

    /// The fewest sheets the busiest reviewer can have after the moves `moves` of `leaver`'s
    /// sheets out of `pairs`, by trying every way of placing them.
    fn least_busiest(pairs: &[Pair], moves: &[(Pair, Option<Pair>)], leaver: Member) -> usize {
        let moved: Vec<Pair> = moves.iter().map(|(old, _)| *old).collect();
        let staying: Vec<Pair> = pairs
            .iter()
            .filter(|p| !moved.contains(p))
            .copied()
            .collect();
        let others: Vec<Member> = pairs
            .iter()
            .flat_map(|p| [p.reviewer, p.author])
            .filter(|&m| m != leaver)
            .collect::<HashSet<_>>()
            .into_iter()
            .collect();
        fn best(i: usize, moved: &[Pair], placed: &mut Vec<Pair>, others: &[Member]) -> usize {
            if i == moved.len() {
                return loads(placed).0.values().copied().max().unwrap_or(0);
            }
            let author = moved[i].author;
            let mut least = usize::MAX;
            for &m in others {
                let pair = Pair {
                    reviewer: m,
                    author,
                };
                if m != author && !placed.contains(&pair) {
                    placed.push(pair);
                    least = least.min(best(i + 1, moved, placed, others));
                    placed.pop();
                }
            }
            least
        }
        best(0, &moved, &mut staying.clone(), &others)
    }

    fn class(n: usize) -> Vec<Member> {
        (0..n as Member).map(|i| 1000 + 7 * i).collect()
    }

    proptest! {
        #[test]
        fn every_sheet_as_often_and_never_ones_own(n in 2usize..150, k in 1usize..=MAX_PER_SHEET, seed: u64) {
            let k = k.min(n - 1);
            let authors = class(n);
            let pairs = hand_out(&authors, k, seed).unwrap();
            prop_assert_eq!(pairs.len(), n * k);
            fair(&pairs).map_err(TestCaseError::fail)?;
            let (reviewing, reviewed) = loads(&pairs);
            for author in &authors {
                prop_assert_eq!(reviewing[author], k);
                prop_assert_eq!(reviewed[author], k);
            }
            // The same round hands out the same, whatever order the authors come in.
            let mut reversed = authors.clone();
            reversed.reverse();
            prop_assert_eq!(hand_out(&reversed, k, seed).unwrap(), pairs);
        }

        #[test]
        fn late_answers_join_within_one(n in 2usize..60, k in 1usize..=4, late in 1usize..8, seed: u64) {
            let k = k.min(n - 1);
            let mut pairs = hand_out(&class(n), k, seed).unwrap();
            let none = HashSet::new();
            for j in 0..late {
                let newcomer = 1 + j as Member;
                let (removed, added) = join(&pairs, &none, newcomer, k, seed ^ newcomer as u64);
                prop_assert_eq!(removed.len(), k);
                prop_assert_eq!(added.len(), 2 * k);
                pairs.retain(|p| !removed.contains(p));
                pairs.extend(added);
                fair(&pairs).map_err(TestCaseError::fail)?;
                let (reviewing, reviewed) = loads(&pairs);
                prop_assert!(reviewing.values().chain(reviewed.values()).all(|&c| c == k));
                // A second joining of the same student changes nothing.
                let (removed, added) = join(&pairs, &none, newcomer, k, seed);
                prop_assert!(removed.is_empty() && added.is_empty());
            }
        }

        #[test]
        fn joining_a_round_nearly_done_stays_within_one(n in 2usize..30, k in 1usize..=3, seed: u64) {
            let k = k.min(n - 1);
            let pairs = hand_out(&class(n), k, seed).unwrap();
            // All but one review done: the newcomer takes what is left, then the least loaded.
            let done: HashSet<Pair> = pairs.iter().skip(1).copied().collect();
            let (removed, added) = join(&pairs, &done, 1, k, seed);
            prop_assert!(removed.len() <= 1);
            prop_assert_eq!(added.len(), 2 * k);
            let mut after: Vec<Pair> = pairs.iter().filter(|p| !removed.contains(p)).copied().collect();
            after.extend(added);
            fair(&after).map_err(TestCaseError::fail)?;
        }

        #[test]
        fn a_leavers_sheets_go_to_others(n in 3usize..12, k in 1usize..=4, seed: u64, leaver in 0usize..12, finished in 0usize..5) {
            let k = k.min(n - 2);
            prop_assume!(k >= 1);
            let authors = class(n);
            let leaver = authors[leaver % n];
            let pairs = hand_out(&authors, k, seed).unwrap();
            let done: HashSet<Pair> = pairs.iter().filter(|p| p.reviewer == leaver).take(finished).copied().collect();
            let moves = reassign(&pairs, &done, leaver, seed);
            prop_assert_eq!(moves.len(), k - done.len().min(k));
            let mut after: Vec<Pair> = pairs.iter().filter(|p| !moves.iter().any(|(old, _)| old == *p)).copied().collect();
            for (old, new) in &moves {
                let new = new.expect("someone can take it");
                prop_assert_eq!(new.author, old.author);
                prop_assert_ne!(new.reviewer, leaver);
                after.push(new);
            }
            // Every sheet still has its k reviews, none twice by one, none by its author;
            // and no other way round gives the busiest stayer fewer sheets.
            let (_, reviewed) = loads(&after);
            for author in &authors {
                prop_assert_eq!(reviewed[author], k);
            }
            prop_assert_eq!(after.iter().collect::<HashSet<_>>().len(), after.len());
            prop_assert!(after.iter().all(|p| p.reviewer != p.author));
            let busiest = |pairs: &[Pair]| loads(pairs).0.values().copied().max().unwrap_or(0);
            prop_assert_eq!(busiest(&after), least_busiest(&pairs, &moves, leaver));
        }
    }

    #[test]
    fn rounds_that_cannot_be_handed_out_say_why() {
        assert!(
            hand_out(&[1], 1, 0)
                .unwrap_err()
                .contains("needs two or more")
        );
        assert!(
            hand_out(&[1, 2, 3], 3, 0)
                .unwrap_err()
                .contains("at most 2")
        );
        assert!(hand_out(&[1, 2, 3], 0, 0).unwrap_err().contains("1 to 10"));
        // Two students review each other.
        let pairs = hand_out(&[5, 9], 1, 3).unwrap();
        assert_eq!(
            pairs.iter().copied().collect::<HashSet<_>>(),
            HashSet::from([
                Pair {
                    reviewer: 5,
                    author: 9
                },
                Pair {
                    reviewer: 9,
                    author: 5
                }
            ])
        );
    }

    #[test]
    fn other_seeds_hand_out_otherwise() {
        let authors = class(30);
        assert_ne!(
            hand_out(&authors, 2, 1).unwrap(),
            hand_out(&authors, 2, 2).unwrap()
        );
    }
}
