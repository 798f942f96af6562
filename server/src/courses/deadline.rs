//! An assignment's deadline and late policy, and what they make of a submission made
//! at a given time: on time, late (with its penalty), or refused after the cutoff.

use jiff::{SignedDuration, Timestamp};
use serde::{Deserialize, Serialize};
use ts_rs::TS;

/// Which of a student's graded submissions gives their score.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum, TS)]
#[serde(rename_all = "snake_case")]
pub enum Counts {
    /// The best score, after each submission's late penalty.
    Best,
    /// The score of the latest graded submission.
    Last,
}

impl Counts {
    pub fn as_str(self) -> &'static str {
        match self {
            Counts::Best => "best",
            Counts::Last => "last",
        }
    }

    pub fn parse(text: &str) -> Counts {
        if text == "last" {
            Counts::Last
        } else {
            Counts::Best
        }
    }

    /// The item that counts among `items` (oldest first), by `score` (the final score
    /// after penalties; `None` for a submission not graded yet or not gradable, which
    /// never counts): the best (the earliest of equals) or the last.
    pub fn choose<T>(
        self,
        items: impl IntoIterator<Item = T>,
        score: impl Fn(&T) -> Option<f64>,
    ) -> Option<T> {
        let graded = items.into_iter().filter(|item| score(item).is_some());
        match self {
            Counts::Best => graded.reduce(|best, item| {
                if score(&item) > score(&best) {
                    item
                } else {
                    best
                }
            }),
            Counts::Last => graded.last(),
        }
    }
}

/// An assignment's dates and late policy.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, TS)]
pub struct Policy {
    #[ts(as = "String")]
    pub due: Timestamp,
    /// The last moment a submission is taken (the due date when there is no grace).
    #[ts(as = "String")]
    pub cutoff: Timestamp,
    /// The share of the score lost per day, or part of a day, after the due date.
    pub penalty_per_day: f64,
    pub counts: Counts,
}

/// How late a submission is and the share of its score that costs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, TS)]
pub struct Lateness {
    /// After the due date by this much (0: on time).
    pub seconds: i64,
    pub penalty: f64,
}

impl Lateness {
    pub const ON_TIME: Lateness = Lateness {
        seconds: 0,
        penalty: 0.0,
    };
}

/// What the policy makes of a submission at some moment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Timing {
    OnTime,
    /// Taken, and marked late by `seconds`; `penalty` is the share of the score lost.
    Late {
        seconds: i64,
        penalty: f64,
    },
    /// Refused: the cutoff has passed.
    Closed,
}

const DAY_SECONDS: i64 = 24 * 3600;

impl Policy {
    /// Whether a submission at `at` is taken, and how late it is.
    pub fn timing(&self, at: Timestamp) -> Timing {
        if at > self.cutoff {
            return Timing::Closed;
        }
        match self.lateness(at) {
            Lateness { seconds: 0, .. } => Timing::OnTime,
            Lateness { seconds, penalty } => Timing::Late { seconds, penalty },
        }
    }

    /// How late a submission made at `at` is by these dates: `t − due`, and the penalty
    /// of every day begun, ⌈(t − due) / 1 day⌉ × penalty, at most the whole score. The
    /// cutoff plays no part: a submission once taken is judged, never refused, so one
    /// taken under dates since replaced is late by as much as it is.
    pub fn lateness(&self, at: Timestamp) -> Lateness {
        let late = at.duration_since(self.due);
        if late <= SignedDuration::ZERO {
            return Lateness::ON_TIME;
        }
        let seconds = late.as_secs().max(1);
        let days = (seconds + DAY_SECONDS - 1) / DAY_SECONDS;
        Lateness {
            seconds,
            penalty: (days as f64 * self.penalty_per_day).min(1.0),
        }
    }
}

/// A length of time in words, as every page and the command line write lateness and
/// time left: `18 s` under a minute, then `40 min`, `5 h 12 min`, `3 days 4 h`.
pub fn span(seconds: i64) -> String {
    let seconds = seconds.max(0);
    let minutes = seconds / 60;
    let (days, hours, minutes) = (minutes / 1440, minutes / 60 % 24, minutes % 60);
    match (days, hours, minutes) {
        (0, 0, 0) => format!("{seconds} s"),
        (0, 0, _) => format!("{minutes} min"),
        (0, _, _) => format!("{hours} h {minutes} min"),
        (1, _, _) => format!("1 day {hours} h"),
        _ => format!("{days} days {hours} h"),
    }
}

/// A penalty as `10%/day` (or `10%`, or `0.1`): the share lost per day late.
pub fn parse_penalty(text: &str) -> Result<f64, String> {
    let bad =
        || format!("{text:?} is not a late penalty: write the share lost per day late, as 10%/day");
    let amount = text.trim().trim_end_matches("/day").trim();
    let share = match amount.strip_suffix('%') {
        Some(percent) => percent.trim().parse::<f64>().map_err(|_| bad())? / 100.0,
        None => amount.parse::<f64>().map_err(|_| bad())?,
    };
    if (0.0..=1.0).contains(&share) {
        Ok(share)
    } else {
        Err(format!(
            "{text:?}: a late penalty is between 0% and 100% per day"
        ))
    }
}

/// A moment with its time zone, as `2026-12-15T23:59+01:00` or `2026-12-15T22:59Z`; a
/// moment without one is refused, since the server's zone is not the course's.
pub fn parse_moment(text: &str) -> Result<Timestamp, String> {
    text.trim().parse::<Timestamp>().map_err(|_| {
        let has_time = text.contains('T');
        if has_time {
            format!(
                "{text:?} is not a moment with a time zone: write it as 2026-12-15T23:59+01:00 (or ...Z for UTC)"
            )
        } else {
            format!(
                "{text:?} has no time: write the date, the time and the zone, as 2026-12-15T23:59+01:00"
            )
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(text: &str) -> Timestamp {
        parse_moment(text).unwrap()
    }

    fn policy() -> Policy {
        Policy {
            due: at("2026-12-15T23:59+01:00"),
            cutoff: at("2026-12-18T23:59+01:00"),
            penalty_per_day: 0.1,
            counts: Counts::Best,
        }
    }

    #[test]
    fn on_time_late_by_days_begun_and_closed_after_the_cutoff() {
        let policy = policy();
        assert_eq!(policy.timing(at("2026-12-15T23:59+01:00")), Timing::OnTime);
        assert_eq!(policy.timing(at("2026-12-01T08:00Z")), Timing::OnTime);
        assert_eq!(
            policy.timing(at("2026-12-16T00:00+01:00")),
            Timing::Late {
                seconds: 60,
                penalty: 0.1
            }
        );
        let Timing::Late { seconds, penalty } = policy.timing(at("2026-12-17T00:00+01:00")) else {
            panic!("late")
        };
        assert_eq!(seconds, 24 * 3600 + 60);
        assert!((penalty - 0.2).abs() < 1e-12);
        assert!(matches!(
            policy.timing(at("2026-12-18T23:59+01:00")),
            Timing::Late { .. }
        ));
        assert_eq!(
            policy.timing(at("2026-12-18T23:59:01+01:00")),
            Timing::Closed
        );
    }

    #[test]
    fn a_submission_taken_is_judged_by_the_dates_now_also_past_their_cutoff() {
        let policy = policy();
        let due = policy.due;
        assert_eq!(policy.lateness(due), Lateness::ON_TIME);
        assert_eq!(
            policy.lateness(due + SignedDuration::from_secs(18)),
            Lateness {
                seconds: 18,
                penalty: 0.1
            }
        );
        // Past the cutoff: refused when submitted, but judged once taken.
        let after = policy.cutoff + SignedDuration::from_hours(1);
        assert_eq!(policy.timing(after), Timing::Closed);
        assert!(policy.lateness(after).penalty > 0.3);
    }

    #[test]
    fn spans_are_in_seconds_under_a_minute() {
        assert_eq!(span(18), "18 s");
        assert_eq!(span(54), "54 s");
        assert_eq!(span(60), "1 min");
        assert_eq!(span(5 * 3600 + 12 * 60 + 5), "5 h 12 min");
        assert_eq!(span(DAY_SECONDS + 3600), "1 day 1 h");
        assert_eq!(span(3 * DAY_SECONDS + 4 * 3600), "3 days 4 h");
        assert_eq!(span(-5), "0 s");
    }

    #[test]
    fn the_penalty_takes_at_most_the_whole_score() {
        let policy = Policy {
            penalty_per_day: 0.6,
            ..policy()
        };
        let Timing::Late { penalty, .. } = policy.timing(at("2026-12-18T12:00Z")) else {
            panic!("late")
        };
        assert_eq!(penalty, 1.0);
    }

    #[test]
    fn penalties_and_moments_are_read_or_refused_with_the_reason() {
        assert_eq!(parse_penalty("10%/day"), Ok(0.1));
        assert_eq!(parse_penalty("25%"), Ok(0.25));
        assert_eq!(parse_penalty("0.05"), Ok(0.05));
        assert!(parse_penalty("ten").unwrap_err().contains("10%/day"));
        assert!(parse_penalty("150%/day").unwrap_err().contains("between"));
        assert!(
            parse_moment("2026-12-15T23:59")
                .unwrap_err()
                .contains("time zone")
        );
        assert!(parse_moment("2026-12-15").unwrap_err().contains("no time"));
        assert_eq!(at("2026-12-15T23:59+01:00"), at("2026-12-15T22:59:00Z"));
    }

    #[test]
    fn the_score_that_counts_is_the_best_or_the_last_graded() {
        let scores = [
            (1, Some(0.5)),
            (2, Some(0.9)),
            (3, Some(0.9)),
            (4, Some(0.7)),
            (5, None),
        ];
        let score = |item: &(i32, Option<f64>)| item.1;
        assert_eq!(Counts::Best.choose(scores, score), Some((2, Some(0.9))));
        assert_eq!(Counts::Last.choose(scores, score), Some((4, Some(0.7))));
        assert_eq!(Counts::Best.choose([(1, None)], score), None);
    }
}
