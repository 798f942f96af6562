//! The grading queue as the server runs it, over a real database and real sandbox
//! workers: students take turns (checked as the order of grading, never as times), and a
//! sandbox that cannot start leaves its submission waiting until it can, never "not
//! gradable". The rule itself, charges and lanes included, is tested in
//! `grading::fair`.

use estlab::clock::{Clock, FixedClock};
use estlab::grading::{Busy, Grader, PhaseAsked, Policy, Secret, Tenant, Work};
use estlab::sandbox::Sandbox;
use estlab::store::{Error, Holder, NewSubmission, Status};
use jiff::Timestamp;
use labs::{Exercise, Language};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::common;
use common::{fixed_secret, store_in};

/// How long a test waits for what it expects before it gives up (a hang, not a time
/// measured: nothing here asserts how long anything took).
const BOUND: Duration = Duration::from_secs(180);

/// The real worker executable.
fn estlab() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_estlab"))
}

/// A file that grades at once (every function throws), for either exercise.
fn quick(marker: &str) -> String {
    format!("function init(){{ throw new Error(\"not implemented\") }} // {marker}\n")
}

/// A submission as a web process beside `grader` takes it.
fn submission<'a>(
    grader: &'a Grader,
    student: &'a str,
    lab: Exercise,
    source: &'a str,
) -> NewSubmission<'a> {
    NewSubmission {
        course: "el2320",
        student,
        member: None,
        lab,
        seed: 7,
        language: labs::Language::JavaScript,
        source,
        submitted_at: Timestamp::UNIX_EPOCH,
        late_seconds: 0,
        penalty: 0.0,
        grader: grader.version(lab),
    }
}

/// One grading at a time, in the foreground only: the order is the queue's alone, however
/// long each grading takes on a busy machine.
fn one_at_a_time() -> Policy {
    Policy {
        parallel: 1,
        demote_after: Duration::MAX,
        heavy: Duration::MAX,
        ..Policy::new(1)
    }
}

fn grader(dir: &Path, sandbox: Sandbox, policy: Policy) -> Arc<Grader> {
    let clock: Arc<dyn Clock> = Arc::new(FixedClock::new(Timestamp::UNIX_EPOCH));
    Grader::with_policy(
        store_in(dir),
        sandbox,
        Secret::read(&fixed_secret(dir)).unwrap(),
        policy,
        clock,
    )
}

/// A student of the course, as the queue takes turns.
fn tenant(who: &str) -> Tenant {
    Tenant::Student {
        course: "el2320".into(),
        student: who.into(),
    }
}

/// The odometry's `wheel_noise` phase of `source`, asked for on the workbench.
fn wheel_noise(source: &str) -> PhaseAsked {
    PhaseAsked {
        exercise: Exercise::Odometry,
        language: Language::JavaScript,
        source: source.to_owned(),
        seed: 7,
        phase: "wheel_noise".to_owned(),
    }
}

/// A file whose `wheel_noise` never ends.
const ENDLESS: &str = "function wheel_noise() { for (;;) {} }";

/// The result of submission `id` once it is graded; panics after `BOUND`.
async fn graded(grader: &Grader, id: i64) -> labs::grading::GradeResult {
    let status = || grader.store().get(id, false).unwrap().unwrap();
    until("the submission graded", || {
        status().summary.status == Status::Graded
    })
    .await;
    status().result.unwrap()
}

/// Waits until `done` holds; panics after `BOUND`.
async fn until(what: &str, mut done: impl FnMut() -> bool) {
    let give_up = Instant::now() + BOUND;
    while !done() {
        assert!(Instant::now() < give_up, "{what} did not happen");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

#[tokio::test]
async fn another_students_submission_is_graded_before_a_flooders_second() {
    let dir = tempfile::tempdir().unwrap();
    let grader = grader(dir.path(), Sandbox::new(estlab(), 1), one_at_a_time());
    let store = grader.store();
    // First, a submission that a web process of another release took, one of whose
    // graders runs: this grader would grade it differently, and leaves it to that one.
    let other_release = "estlab 0.0.1 plan 000000000000";
    store
        .heartbeat(
            &Holder::this_process(),
            (&[other_release], &[Language::JavaScript]),
            Timestamp::MAX - jiff::SignedDuration::from_hours(1),
        )
        .unwrap();
    let elsewhere = store
        .insert(
            &NewSubmission {
                grader: other_release,
                ..submission(&grader, "alan", Exercise::Odometry, &quick("alan"))
            },
            Timestamp::MAX,
        )
        .unwrap();
    // And one of a release whose graders are all gone (an upgrade): taken over.
    let taken_over = store
        .insert(
            &NewSubmission {
                grader: "estlab 0.0.0 plan 000000000000",
                ..submission(&grader, "barbara", Exercise::Odometry, &quick("barbara"))
            },
            Timestamp::MAX,
        )
        .unwrap();
    // The submissions a stop left waiting: a flooder's two (one per exercise) first, then
    // two other students' one each.
    let ids: Vec<i64> = [
        ("mallory", Exercise::EkfLocalization),
        ("mallory", Exercise::Odometry),
        ("ada", Exercise::EkfLocalization),
        ("grace", Exercise::Odometry),
    ]
    .iter()
    .map(|(student, lab)| {
        let source = quick(student);
        store
            .insert(&submission(&grader, student, *lab, &source), Timestamp::MAX)
            .unwrap()
    })
    .collect();
    assert_eq!(grader.resume().unwrap(), 5);
    until("every submission of this release graded", || {
        store
            .all_submissions()
            .unwrap()
            .iter()
            .all(|s| s.status == Status::Graded || s.id == elsewhere)
    })
    .await;
    // The first in line, and never taken; the other graded here, as this grader grades.
    let left = store.get(elsewhere, false).unwrap().unwrap();
    assert_eq!(left.summary.status, Status::Queued);
    let taken = store.get(taken_over, false).unwrap().unwrap();
    assert_eq!(
        taken.grader.as_deref(),
        Some(grader.version(Exercise::Odometry))
    );

    let mut graded: Vec<(String, i64)> = ids
        .iter()
        .map(|&id| {
            let s = store.get(id, false).unwrap().unwrap();
            assert!(s.result.unwrap().gradable, "submission {id}");
            (s.graded_at.unwrap(), id)
        })
        .collect();
    graded.sort();
    let order: Vec<i64> = graded.into_iter().map(|(_, id)| id).collect();
    // Mallory's first, then everybody else's first, then Mallory's second; first come
    // first served would have graded Mallory's two one after the other.
    assert_eq!(order, [ids[0], ids[2], ids[3], ids[1]]);
}

/// A web process beside graders of JavaScript only: a student's MATLAB file waits for a
/// grader that runs Octave, and their JavaScript file is taken meanwhile (it was refused
/// 409 while the MATLAB one waited forever); a second MATLAB file still waits its turn.
#[tokio::test]
async fn a_file_no_running_grader_grades_holds_back_none_in_another_language() {
    let dir = tempfile::tempdir().unwrap();
    // Not resumed: a web process that leaves grading to graders.
    let web = grader(dir.path(), Sandbox::new(estlab(), 1), one_at_a_time());
    web.store()
        .heartbeat(
            &Holder::this_process(),
            (&web.versions(), &[Language::JavaScript]),
            Timestamp::now(),
        )
        .unwrap();
    let in_language = |language, source| NewSubmission {
        language,
        ..submission(&web, "ada", Exercise::Odometry, source)
    };
    let matlab = web
        .submit(&in_language(Language::Matlab, "% mine"))
        .unwrap();
    assert!(matches!(
        web.submit(&in_language(Language::Matlab, "% again")),
        Err(Error::Busy(id)) if id == matlab
    ));
    let javascript = web
        .submit(&in_language(Language::JavaScript, "// mine"))
        .unwrap();
    assert!(matches!(
        web.submit(&in_language(Language::JavaScript, "// again")),
        Err(Error::Busy(id)) if id == javascript
    ));
}

#[tokio::test]
async fn a_sandbox_that_cannot_start_leaves_the_submission_waiting_until_it_can() {
    let dir = tempfile::tempdir().unwrap();
    let bin = tempfile::tempdir().unwrap();
    // The worker's executable is missing, as a spawn fails when no descriptor, memory or
    // process is left: the server's fault, not the student's.
    let worker = bin.path().join("estlab");
    let grader = grader(
        dir.path(),
        Sandbox::new(worker.clone(), 1),
        Policy {
            first_retry: Duration::from_millis(20),
            ..one_at_a_time()
        },
    );
    grader.resume().unwrap();
    let source = quick("waiting");
    let id = grader
        .submit(&submission(
            &grader,
            "ada",
            Exercise::EkfLocalization,
            &source,
        ))
        .unwrap();

    // Tried, failed, tried again: still waiting, not "not gradable".
    until("two failed starts (or an end)", || {
        grader
            .waiting()
            .iter()
            .any(|w| w.work == Work::Submission(id) && w.failed_starts >= 2)
            || grader
                .store()
                .get(id, false)
                .unwrap()
                .unwrap()
                .summary
                .status
                == Status::Graded
    })
    .await;
    let waiting = grader.store().get(id, false).unwrap().unwrap();
    assert_eq!(waiting.summary.status, Status::Queued);
    assert!(waiting.result.is_none(), "{:?}", waiting.result);
    // It still counts as the student's one waiting submission.
    assert!(matches!(
            grader
                .store()
                .insert(
    &submission(&grader, "ada", Exercise::EkfLocalization, "// again"),
    Timestamp::MAX,
    ),
            Err(Error::Busy(busy)) if busy == id
        ));

    // The fault is gone: the next try grades it.
    std::os::unix::fs::symlink(estlab(), &worker).unwrap();
    let result = graded(&grader, id).await;
    assert!(result.gradable, "{:?}", result.reason);
    assert_eq!(result.score, 0.0);
    assert!(grader.waiting().is_empty());
}

/// Phases asked for on the workbench take their turn with everything else the sandbox
/// does: a student whose endless loops wait in line does not hold a classmate's run
/// behind all of them (first come, first served did), and a run that cannot start within
/// its asker's patience leaves the line with its place, its code not run.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn another_students_phase_runs_before_a_flooders_next_ones() {
    let dir = tempfile::tempdir().unwrap();
    let grader = grader(dir.path(), Sandbox::new(estlab(), 1), one_at_a_time());
    let finished: Arc<std::sync::Mutex<Vec<&str>>> = Arc::default();
    let ask = |who: &'static str, source: &str, patience: Duration| {
        let (grader, finished) = (Arc::clone(&grader), Arc::clone(&finished));
        let asked = wheel_noise(source);
        tokio::spawn(async move {
            let outcome = grader.phase(tenant(who), asked, patience).await;
            if outcome.is_ok() {
                finished.lock().unwrap().push(who);
            }
            outcome
        })
    };
    let flood: Vec<_> = (0..3).map(|_| ask("mallory", ENDLESS, BOUND)).collect();
    until("Mallory's first running, two waiting", || {
        grader.running() == 1 && grader.waiting().len() == 2
    })
    .await;

    // Ada's run cannot start while Mallory's holds the one place: with no patience, she
    // is told her place (Mallory's next ones go behind her) and her run leaves the line.
    let busy = ask("ada", &quick("ada"), Duration::ZERO).await.unwrap();
    let Err(Busy { place }) = busy else {
        panic!("started at once beside an endless loop: {busy:?}")
    };
    assert_eq!(place, 1, "Mallory has one running: Ada is next");
    assert!(
        grader
            .waiting()
            .iter()
            .all(|w| !matches!(&w.tenant, Tenant::Student { student, .. } if student == "ada")),
        "{:?}",
        grader.waiting()
    );

    // With patience, her run goes next, before Mallory's second and third.
    let ada = ask("ada", &quick("ada"), BOUND).await.unwrap();
    let outputs = ada.expect("in time").expect("run");
    assert!(outputs.functions[0].error.is_some(), "{outputs:?}");
    for looped in flood {
        let outputs = looped.await.unwrap().expect("in time").expect("run");
        let stopped = outputs.functions[0].stopped.as_ref().expect("stopped");
        assert_eq!(stopped.cause, labs::grading::Cause::Time);
    }
    assert_eq!(
        *finished.lock().unwrap(),
        ["mallory", "ada", "mallory", "mallory"]
    );
    // Each is charged the CPU time its sandbox used: Mallory's three loops ran to their
    // limit of 2 s each (6 s, a little decayed since), Ada's run threw at once.
    let (mallory, ada) = (
        grader.charge(&tenant("mallory")),
        grader.charge(&tenant("ada")),
    );
    assert!(mallory >= 4.0, "Mallory charged {mallory} s");
    assert!(ada < 1.0, "Ada charged {ada} s");
}

/// A grading whose worker the machine gives no time (here: a worker that stops itself
/// with SIGSTOP, the first time only) runs out of time by the clock with its CPU time
/// unused: the machine's doing, never the student's verdict ("not gradable" until now).
/// It goes back in line and the next try grades it, and its student is charged only
/// the CPU time used.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_grading_the_machine_starves_waits_and_is_tried_again() {
    let dir = tempfile::tempdir().unwrap();
    let bin = tempfile::tempdir().unwrap();
    let worker = bin.path().join("estlab");
    let stopped = bin.path().join("stopped");
    std::fs::write(
        &worker,
        format!(
            "#!/bin/sh\nif /bin/mkdir {} 2>/dev/null; then kill -STOP $$; fi\nexec {} \"$@\"\n",
            stopped.display(),
            estlab().display()
        ),
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&worker, std::fs::Permissions::from_mode(0o755)).unwrap();
    let sandbox = Sandbox::new(worker, 1).with_clock_limit(Duration::from_secs(2));
    let grader = grader(
        dir.path(),
        sandbox,
        Policy {
            first_retry: Duration::from_millis(20),
            ..one_at_a_time()
        },
    );
    grader.resume().unwrap();
    let source = quick("starved");
    let id = grader
        .submit(&submission(&grader, "ada", Exercise::Odometry, &source))
        .unwrap();
    let result = graded(&grader, id).await;
    assert!(stopped.is_dir(), "the first worker stopped itself");
    assert!(result.gradable, "{:?}", result.reason);
    assert_eq!(result.score, 0.0);
    // The stopped worker held its place for 2 s by the clock without computing: its
    // student is charged CPU time, not that.
    let charge = grader.charge(&tenant("ada"));
    assert!(charge < 1.0, "charged {charge} s");
}

/// A report's runs take their turn with the rest (until now each web process made them
/// one submission at a time, first come first served, in a line of their own): behind a
/// student's endless loop, a classmate's report runs go before that student's own.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn report_runs_take_their_turn_with_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    let grader = grader(dir.path(), Sandbox::new(estlab(), 1), one_at_a_time());
    let finished: Arc<std::sync::Mutex<Vec<String>>> = Arc::default();
    let endless = {
        let (grader, finished) = (Arc::clone(&grader), Arc::clone(&finished));
        tokio::spawn(async move {
            let outcome = grader
                .phase(tenant("mallory"), wheel_noise(ENDLESS), BOUND)
                .await;
            finished.lock().unwrap().push("mallory's phase".to_owned());
            outcome
        })
    };
    until("Mallory's endless loop running", || {
        grader.running() == 1 && grader.waiting().is_empty()
    })
    .await;
    let report = |who: &'static str| {
        let (grader, finished) = (Arc::clone(&grader), Arc::clone(&finished));
        let runs: Vec<&'static str> = Exercise::EkfLocalization
            .declaration()
            .report
            .iter()
            .map(|r| r.run)
            .collect();
        let source = quick(who);
        tokio::spawn(async move {
            let outputs = grader
                .report_runs(
                    tenant(who),
                    Exercise::EkfLocalization,
                    (Language::JavaScript, source),
                    3,
                    runs,
                )
                .await;
            finished.lock().unwrap().push(format!("{who}'s report"));
            outputs
        })
    };
    let mallory = report("mallory");
    until("Mallory's report runs waiting", || {
        grader.waiting().len() == 1
    })
    .await;
    let ada = report("ada");
    until("both waiting", || grader.waiting().len() == 2).await;
    for outputs in [ada.await.unwrap(), mallory.await.unwrap()] {
        let outputs = outputs.expect("run");
        assert_eq!(outputs.runs.len(), 4, "{outputs:?}");
        assert!(outputs.runs.iter().all(|run| run.error.is_some()));
    }
    endless.await.unwrap().expect("in time").expect("run");
    assert_eq!(
        *finished.lock().unwrap(),
        ["mallory's phase", "ada's report", "mallory's report"]
    );
}
