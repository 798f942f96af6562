//! Grading the sensor-fusion exercise: the tests of the functions (as every exercise's
//! are graded), and a test per trial, which earns its points when the student's
//! functions, strung together by the harness's fusion loop, give the reference filter's
//! belief after every step; on the server, the class challenge's figure of the student's
//! filter over the held-out trial.

use super::contract::FUNCTIONS;
use super::job::{FilterSettings, TrialRecord};
use super::plan::{HELD_OUT, HeldOut, Plan, RUN_LIMIT_MS, TrialSpec};
use crate::Exercise;
use crate::fusion::{Errors, REPORT_FIGURES, Settings, inside_three_sigma};
use crate::grading::STEP_BY_STEP;
use crate::grading::{
    self, Beliefs, Cause, Challenge, FunctionVerdicts, GradeResult, Mismatch, Outputs, RunOutput,
    Subject, Test, follows, function_tests,
};

/// Grades what the harness reported. Tests whose outputs are missing fail as not run.
pub fn grade(plan: &Plan, outputs: &Outputs) -> GradeResult {
    let (mut tests, functions) = function_tests(&plan.cases, &outputs.functions);
    for spec in &plan.runs {
        let output = outputs.runs.iter().find(|run| run.name == spec.name);
        tests.push(trial_test(spec, output, &functions));
    }
    let mut result = GradeResult::graded(
        Exercise::SensorFusion,
        plan.seed,
        plan.hidden.is_some(),
        tests,
    );
    result.challenge = plan.held_out.as_ref().map(|held_out| {
        let output = outputs.runs.iter().find(|run| run.name == HELD_OUT);
        challenge(held_out, output)
    });
    result
}

/// The class challenge's figure: the RMS position error of the student's filter, with
/// the settings their `tuning()` chose, over the held-out trial, to a tenth of a
/// millimetre. Nothing of the trial reaches the student but the figures: what their code
/// said once the trial's data reached it, or where it stopped, is not repeated (it could
/// carry the readings out).
fn challenge(held_out: &HeldOut, output: Option<&RunOutput>) -> Challenge {
    let steps = held_out.trial.steps.len();
    let reference = &held_out.reference;
    let (figure, measured) = match output.map(|run| measure(held_out, run)) {
        Some(Ok((errors, settings, inside))) => (
            Some(tenth_of_a_millimetre(errors.rms)),
            format!(
                "Your filter, with tuning() = {{k_xy: {}, k_theta: {}, c_xy: {}, \
                 field_of_view: {}, lambda: {}}}: RMS {:.4} m, mean {:.4} m, largest {:.3} m; \
                 the truth inside its 3-sigma ellipse at {:.0} % of the steps.",
                settings.k_xy,
                settings.k_theta,
                settings.c_xy,
                js_number(settings.field_of_view),
                js_number(settings.lambda),
                errors.rms,
                errors.mean,
                errors.max,
                100.0 * inside
            ),
        ),
        Some(Err(why)) => (None, why),
        None => (
            None,
            "Your filter did not run over the held-out trial.".to_owned(),
        ),
    };
    let defaults = Settings::default();
    let report = REPORT_FIGURES
        .map(|r| format!("{} m", r.kalman))
        .join(" and ");
    Challenge {
        measure: format!("the RMS position error over a held-out trial of {steps} steps"),
        unit: "m".to_owned(),
        figure,
        reference: tenth_of_a_millimetre(reference.filter.rms),
        message: [
            measured,
            format!(
                "The reference filter with its default settings (k_xy = {}, k_theta = {}, \
                 c_xy = {}, a {} m field of view, a gate at {} %): RMS {:.4} m, mean {:.4} m; \
                 odometry alone: RMS {:.4} m. The report's own Kalman filter, on its two real \
                 trials: mean errors of {report}.",
                defaults.process_xy,
                defaults.process_theta,
                defaults.noise.c_xy,
                defaults.field_of_view,
                100.0 * defaults.gate,
                reference.filter.rms,
                reference.filter.mean,
                reference.odometry.rms,
            ),
        ]
        .join("\n"),
    }
}

/// The errors of the student's run over the held-out trial, the settings it used and the
/// share of steps whose truth lies inside its 3-sigma ellipse; or why there are none.
fn measure(held_out: &HeldOut, run: &RunOutput) -> Result<(Errors, FilterSettings, f64), String> {
    if let Some(stopped) = &run.stopped {
        return Err(format!(
            "Your filter was stopped on the held-out trial: {}.",
            match &stopped.cause {
                Cause::Time => format!(
                    "its run took more than the {} s it may",
                    RUN_LIMIT_MS / 1000
                ),
                Cause::Cancelled => "it was cancelled".to_owned(),
                Cause::Other(what) => what.clone(),
            }
        ));
    }
    let record: TrialRecord = run.record().map_err(|_| {
        "The harness's record of the held-out trial is unreadable, which happens when a file \
         changes built-in objects."
            .to_owned()
    })?;
    if let Some(error) = &run.error {
        // Before tuning() returned, the code had seen nothing of the trial.
        return Err(match (&run.recorded, &record.tuning) {
            (Some(_), None) => format!("Your filter did not start on the held-out trial: {error}"),
            _ => "Your filter stopped on the held-out trial: it threw, or returned what the \
                  loop cannot use. What it said is not shown, so that the trial stays unseen: \
                  the graded trials run the same functions and show where they fail."
                .to_owned(),
        });
    }
    let settings = record
        .tuning
        .ok_or("The held-out trial ran without tuning()'s settings.")?;
    let steps = held_out.trial.steps.len();
    let truths = held_out.trial.steps.iter().map(|s| s.truth);
    if record.poses.len() != steps || record.covariances.len() != steps {
        return Err(format!(
            "Your filter recorded {} of the held-out trial's {steps} steps.",
            record.poses.len()
        ));
    }
    let errors = Errors::of(record.poses.iter().copied().zip(truths.clone()))
        .filter(|e| e.rms.is_finite())
        .ok_or("Your filter's estimate over the held-out trial is not a finite number.")?;
    let inside = record
        .poses
        .iter()
        .zip(&record.covariances)
        .zip(truths)
        .filter(|((pose, sigma), truth)| inside_three_sigma(**pose, sigma, *truth))
        .count();
    Ok((errors, settings, inside as f64 / steps as f64))
}

/// A length in metres to the tenth of a millimetre: what the challenge ranks by, and no
/// finer, so that a figure says little of the trial beyond itself.
fn tenth_of_a_millimetre(metres: f64) -> f64 {
    libm::round(metres * 1e4) / 1e4
}

/// A number as JavaScript writes it (`Infinity`, not Rust's `inf`).
fn js_number(value: f64) -> String {
    if value.is_infinite() {
        "Infinity".to_owned()
    } else {
        value.to_string()
    }
}

/// The test of a trial: passed when the run follows the reference at every step.
fn trial_test(spec: &TrialSpec, output: Option<&RunOutput>, functions: &FunctionVerdicts) -> Test {
    let steps = spec.steps();
    let outcome = output.map_or_else(|| Err("not run".to_owned()), |run| departure(spec, run));
    let passed = outcome.is_ok();
    let mut verdict = if passed {
        format!("Passed: the belief follows the reference filter's at each of the {steps} steps.")
    } else {
        "Failed: the belief must follow the reference filter's at every step.".to_owned()
    };
    if !passed {
        verdict += &functions.explain();
    }
    let s = &spec.settings;
    let mut lines = vec![
        verdict,
        format!(
            "The trial: {steps} steps of 0.28 s, k_xy = {}, k_theta = {}, c_xy = {}, a field \
             of view of {} m and a gate of {:.4} (chi2inv(0.999, 3)), from the odometry's \
             first pose with standard deviations {:?}. Poses must match within {:e} (x and y \
             in metres, the heading in radians, modulo 2 pi), covariances within {:e} of \
             their largest element (or {:e}).",
            s.process_xy,
            s.process_theta,
            s.noise.c_xy,
            s.field_of_view,
            s.gate_threshold(),
            s.start_sigma,
            STEP_BY_STEP.pose.absolute,
            STEP_BY_STEP.covariance_share,
            STEP_BY_STEP.covariance_floor,
        ),
    ];
    if let Err(departure) = outcome {
        lines.push(format!("{}: {departure}", spec.name));
    }
    Test::all_or_nothing(
        Subject::Run(spec.name.clone()),
        format!("{} trial: {}", spec.name, FUNCTIONS.join(", ")),
        passed,
        lines.join("\n"),
    )
}

/// Where the student's run first departs from the reference (or what stopped it), or
/// nothing when it follows it throughout.
fn departure(spec: &TrialSpec, output: &RunOutput) -> Result<(), String> {
    let record: TrialRecord = output.completed(RUN_LIMIT_MS)?;
    let reference = spec.reference_record();
    follows(NAMES, beliefs(&record), beliefs(&reference), STEP_BY_STEP)
}

/// The first step (counted from 1) at which the beliefs `record` holds leave the
/// reference's, with the first element that differs there; none while they follow it as
/// far as they go.
pub fn first_departure(spec: &TrialSpec, record: &TrialRecord) -> Option<(usize, Mismatch)> {
    let reference = spec.reference_record();
    grading::first_departure(NAMES, beliefs(record), beliefs(&reference), STEP_BY_STEP)
}

/// What the belief's parts are called in messages.
const NAMES: [&str; 2] = ["mu", "sigma"];

fn beliefs(record: &TrialRecord) -> Beliefs<'_> {
    Beliefs {
        poses: &record.poses,
        covariances: &record.covariances,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fusion::{Detector, run};
    use crate::grading::{Hidden, Stopped};
    use serde_json::json;

    fn held_out() -> HeldOut {
        let plan = Plan::new(
            3,
            Some(Hidden {
                cases: 11,
                class: 12,
            }),
        );
        plan.held_out.expect("the server's plan has one")
    }

    /// What the loop records over the held-out trial with `settings` (the default
    /// ones'), the reference's beliefs, cut to the first `steps`.
    fn recorded(held_out: &HeldOut, tuning: Option<FilterSettings>, steps: usize) -> RunOutput {
        let estimates = run(&held_out.trial, &Settings::default(), &Detector::default());
        let record = TrialRecord {
            tuning,
            poses: estimates.iter().take(steps).map(|e| e.pose).collect(),
            covariances: estimates.iter().take(steps).map(|e| e.sigma).collect(),
        };
        RunOutput {
            name: HELD_OUT.to_owned(),
            error: None,
            stopped: None,
            recorded: Some(serde_json::to_value(record).unwrap()),
        }
    }

    fn defaults() -> FilterSettings {
        let s = Settings::default();
        FilterSettings {
            k_xy: s.process_xy,
            k_theta: s.process_theta,
            c_xy: s.noise.c_xy,
            field_of_view: s.field_of_view,
            lambda: s.gate_threshold(),
        }
    }

    /// The reference's own beliefs with the default settings score the reference's
    /// figure, and the message says what the settings were.
    #[test]
    fn the_reference_settings_score_the_reference_figure() {
        let held_out = held_out();
        let steps = held_out.trial.steps.len();
        let challenge = challenge(
            &held_out,
            Some(&recorded(&held_out, Some(defaults()), steps)),
        );
        assert_eq!(challenge.figure, Some(challenge.reference));
        assert!(challenge.reference > 0.0 && challenge.reference < 0.5);
        assert!(challenge.measure.contains(&format!("{steps} steps")));
        assert!(
            challenge.message.contains("k_xy: 0.05"),
            "{}",
            challenge.message
        );
        assert!(challenge.message.contains("0.139 m and 0.057 m"));
    }

    /// The starter's `tuning()` returns the reference's default settings, to the last
    /// digit: a file that keeps it scores the reference's figure.
    #[test]
    fn the_starter_tunes_as_the_reference_does() {
        let d = defaults();
        let settings = format!(
            "return {{\n    k_xy: {}, k_theta: {}, c_xy: {}, field_of_view: {},\n    lambda: {},\n  }};",
            d.k_xy, d.k_theta, d.c_xy, d.field_of_view, d.lambda
        );
        let starters = &crate::exercises::Exercise::SensorFusion
            .declaration()
            .starters;
        assert!(starters.javascript.contains(&settings), "{settings}");
        let settings = format!(
            "return {{\n        \"k_xy\": {}, \"k_theta\": {}, \"c_xy\": {}, \"field_of_view\": {},\n        \"lambda\": {},\n    }}",
            d.k_xy, d.k_theta, d.c_xy, d.field_of_view, d.lambda
        );
        assert!(starters.python.contains(&settings), "{settings}");
    }

    /// What the student's code said after the trial's data reached it is not repeated;
    /// what it said before (loading the file, in tuning()) is.
    #[test]
    fn what_the_code_said_over_the_trial_stays_unseen() {
        let held_out = held_out();
        let mut threw = recorded(&held_out, Some(defaults()), 40);
        threw.error = Some("at step 41, predict: threw Error: 0.8131 1.2207".to_owned());
        let challenge = challenge(&held_out, Some(&threw));
        assert_eq!(challenge.figure, None);
        assert!(
            challenge.message.contains("it threw"),
            "{}",
            challenge.message
        );
        assert!(!challenge.message.contains("0.8131") && !challenge.message.contains("41"));

        // Stopped by the host: the cause, not where.
        let stopped = RunOutput::stopped(
            HELD_OUT,
            Stopped {
                during: "held-out: at step 977, update".to_owned(),
                cause: Cause::Time,
                limit_ms: None,
            },
        );
        let challenge = super::challenge(&held_out, Some(&stopped));
        assert!(
            challenge.message.contains("more than the 5 s"),
            "{}",
            challenge.message
        );
        assert!(!challenge.message.contains("977"));

        let mut early = recorded(&held_out, None, 0);
        early.error = Some("calling tuning(): threw ReferenceError: x is not defined".into());
        let challenge = super::challenge(&held_out, Some(&early));
        assert_eq!(challenge.figure, None);
        assert!(
            challenge.message.contains("x is not defined"),
            "{}",
            challenge.message
        );
    }

    /// A run that gives no usable estimate has no figure, and says why.
    #[test]
    fn estimates_that_cannot_be_measured_have_no_figure() {
        let held_out = held_out();
        let steps = held_out.trial.steps.len();
        let short = recorded(&held_out, Some(defaults()), steps - 1);
        assert!(
            challenge(&held_out, Some(&short))
                .message
                .contains("recorded")
        );

        let mut diverged = recorded(&held_out, Some(defaults()), steps);
        // The loop records finite numbers only; their squares may still overflow.
        diverged.recorded.as_mut().unwrap()["poses"][5] = json!([1e300, 0.0, 0.0]);
        let result = challenge(&held_out, Some(&diverged));
        assert_eq!(result.figure, None);
        assert!(
            result.message.contains("not a finite number"),
            "{}",
            result.message
        );

        assert!(challenge(&held_out, None).message.contains("did not run"));
    }
}
