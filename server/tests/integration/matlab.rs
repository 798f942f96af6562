//! Students' files in MATLAB, graded as the server grades them: GNU Octave in its
//! operating-system sandbox, called by the harness in QuickJS (see
//! `server/src/sandbox/native`), the lab's conventions converted both ways. A correct file
//! of each exercise scores 1 with hidden cases, written as the lab's students write (the
//! lab's own signatures and shapes; functions with or without `end`); a sample of classic
//! mistakes each fails its function with its hint; the lab's editions that read the map
//! and the noise from globals grade as they are; and what a student might try from inside
//! is contained, with a precise message, while the other tests pass. Needs `bwrap` and
//! Octave (Debian's bubblewrap and octave, which `scripts/test` installs).

use crate::student;

use estlab::sandbox::{Code, Sandbox};
use labs::grading::{GradeResult, Hidden, Status, Subject};
use labs::{Exercise, Language};
use std::path::PathBuf;
use student::catalogue::{Seeds, failing_alone};
use student::matlab::{EKF_LOCALIZATION, ODOMETRY, SENSOR_FUSION, UKF_PARTICLE};

const SEEDS: [Seeds; 2] = [(1, 0x5eed_0001), (2320, 9_876_543_210)];

#[test]
fn the_correct_files_score_1_with_hidden_cases() {
    for files in [EKF_LOCALIZATION, ODOMETRY, SENSOR_FUSION, UKF_PARTICLE] {
        files.check_the_correct_file(&SEEDS[..1]);
    }
}

#[test]
fn the_starters_score_0_and_say_what_is_not_implemented() {
    for files in [ODOMETRY, SENSOR_FUSION, UKF_PARTICLE] {
        files.check_the_starter(SEEDS[0]);
    }
    let starter = Exercise::EkfLocalization
        .declaration()
        .starter(Language::Matlab);
    let result = grade(Exercise::EkfLocalization, starter);
    assert_eq!(result.score, 0.0);
    for test in &result.tests {
        let thrown = match &test.subject {
            Subject::Function(name) => format!("threw error: {name}: not implemented (line"),
            Subject::Run(_) => "threw error: init: not implemented (line".to_owned(),
        };
        assert!(test.message.contains(&thrown), "{}", test.message);
    }
}

#[test]
fn a_sample_of_mistakes_each_fails_its_function_with_its_hint() {
    for files in [EKF_LOCALIZATION, ODOMETRY, SENSOR_FUSION, UKF_PARTICLE] {
        files.check_a_sample_of_mistakes(&SEEDS[..1]);
    }
}

/// The lab's later edition reads the map, the threshold and the noise from globals
/// (`observation_model(x, j)`, `associate(mu_bar, sigma_bar, z_i)`, `predict(mu, sigma,
/// u)`); its `init()` takes no data set. Such files grade as they are.
#[test]
fn the_labs_edition_with_globals_grades_as_it_is() {
    let globals = "
function [mu_bar, sigma_bar] = predict(mu, sigma, u)
  global R
  mu_bar = mu + u;
  G = [1, 0, -u(2); 0, 1, u(1); 0, 0, 1];
  sigma_bar = symmetrise(G * sigma * G' + R);
end

function z_hat = observation_model(x, j)
  global map
  dx = map(1, j) - x(1);
  dy = map(2, j) - x(2);
  z_hat = [hypot(dx, dy); wrap(atan2(dy, dx) - x(3))];
end

function [c, outlier, nu, S, H] = associate(mu_bar, sigma_bar, z_i)
  global map lambda_m Q
  [c, outlier, nu, S, H] = associate_all(mu_bar, sigma_bar, z_i, map, lambda_m, Q);
end
";
    let source = EKF_LOCALIZATION
        .correct
        .replace(
            "function [c, outlier, nu, S, H] = associate(",
            "function [c, outlier, nu, S, H] = associate_all(",
        )
        .replace(
            "= associate(mu_bar, sigma_bar, z(:, i), M, Lambda_M, Q);",
            "= associate_all(mu_bar, sigma_bar, z(:, i), M, Lambda_M, Q);",
        )
        .replace(
            "z_hat = observation_model(mu_bar, M, j);",
            "z_hat = observation_model_of(mu_bar, M, j);",
        )
        .replace(
            "function z_hat = observation_model(x, M, j)",
            "function z_hat = observation_model_of(x, M, j)",
        )
        .replace(
            "function [mu_bar, sigma_bar] = predict(mu, sigma, u, R)",
            "function [mu_bar, sigma_bar] = predict_with(mu, sigma, u, R)",
        )
        + globals;
    let result = grade(Exercise::EkfLocalization, &source);
    for test in &result.tests {
        assert_eq!(
            test.status,
            Status::Passed,
            "{}: {}",
            test.name,
            test.message
        );
    }

    // One setting for all three data sets: the runs it does not suit fail, no more.
    let source = EKF_LOCALIZATION.correct.replace(
        "function [mu, sigma, R, Q, Lambda_M] = init(dataset)",
        "function [mu, sigma, R, Q, Lambda_M] = init()\n  dataset = 'o3';",
    );
    let result = grade(Exercise::EkfLocalization, &source);
    let passed = |name: &str| {
        result
            .tests
            .iter()
            .find(|t| t.subject == Subject::Run(name.to_owned()))
            .map(|t| t.status == Status::Passed)
    };
    assert_eq!(passed("o3"), Some(true));
    assert_eq!(passed("no-odometry"), Some(false));
}

fn sandbox() -> Sandbox {
    Sandbox::new(PathBuf::from(env!("CARGO_BIN_EXE_estlab")), 2)
}

fn grade(exercise: Exercise, source: &str) -> GradeResult {
    let code = Code {
        language: Language::Matlab,
        text: source,
    };
    let hidden = Hidden {
        cases: 77,
        class: 78,
    };
    sandbox().grade(exercise, code, 5, Some(hidden))
}

/// What `wheel_noise`'s test says when the correct odometry file's `wheel_noise` has
/// `body` (a later definition wins), once it is known that only it and the runs (which
/// call it) failed and that the result is gradable: the student's code, not the sandbox.
fn wheel_noise_message(body: &str) -> String {
    let source = format!(
        "{}\nfunction Sigma_delta = wheel_noise(ds_r, ds_l, k_r, k_l)\n{body}\nend\n",
        ODOMETRY.correct
    );
    failing_alone(&grade(Exercise::Odometry, &source), "wheel_noise")
}

fn contained(body: &str, expected: &str) {
    let message = wheel_noise_message(body);
    assert!(
        message.contains(expected),
        "expected {expected:?} in: {message}"
    );
}

#[test]
fn the_file_system_holds_the_interpreter_and_nothing_of_the_server() {
    let data = tempfile::tempdir().unwrap();
    let secret = data.path().join("secret");
    std::fs::write(&secret, "the server's secret").unwrap();
    contained(
        &format!("  Sigma_delta = fileread('{}');", secret.display()),
        "threw error: fileread: cannot open file",
    );
    contained(
        "  listed = dir('/'); error('root %s', strjoin(sort({listed.name}), ' '));",
        "root . .. bin dev etc lib lib64 proc tmp usr",
    );
    contained(
        "  [fid, why] = fopen('/usr/evil', 'w'); error('usr %d %s', fid, why);",
        "usr -1 Read-only file system",
    );
    contained(
        "  [fid, why] = fopen('/proc/sys/kernel/core_pattern', 'w'); error('core %d %s', fid, why);",
        "core -1 Read-only file system",
    );
}

#[test]
fn no_processes_and_no_network() {
    contained(
        "  [status, out] = system('id'); error('system %d %s', status, out);",
        "threw error: system: unable to start subprocess for 'id' (line",
    );
    contained(
        "  Sigma_delta = urlread('http://127.0.0.1:80/');",
        "threw error: urlread: Couldn't connect to server (line",
    );
}

#[test]
fn endless_work_memory_disk_and_huge_answers_are_stopped_with_a_message() {
    // Octave's phases have four times the limit: 2 s becomes 8.
    contained(
        "  while true, end",
        "Stopped after 8 s, the time limit, while running wheel_noise/",
    );
    // A built-in on a huge matrix, which Octave does not interrupt: the CPU clock is read
    // from outside.
    contained(
        "  a = ones(3000); Sigma_delta = a * a * a * a * a * a * a * a * a * a * a * a;",
        "Stopped after 8 s, the time limit, while running wheel_noise/",
    );
    contained(
        "  Sigma_delta = ones(1e5);",
        "threw error: out of memory or dimension too large for Octave's index type",
    );
    contained(
        "  fid = fopen('/tmp/fill', 'w'); fwrite(fid, zeros(1, 2^21)); fclose(fid); \
         error('wrote %d', dir('/tmp/fill').bytes);",
        "threw error: wrote 1048576",
    );
    contained(
        "  Sigma_delta = zeros(1000);",
        "returned an array of 1000000 values, more than the 2000 a call may return",
    );
    contained(
        "  Sigma_delta = [1 + 2i, 0; 0, 1];",
        "returned a complex number, where the contract has real ones",
    );
    // What the student's code prints goes nowhere.
    contained(
        "  for k = 1:2000, disp(repmat('x', 1, 1000)); end\n  Sigma_delta = 'printed';",
        "wheel_noise",
    );
}

#[test]
fn ending_octave_or_printing_a_reply_harms_only_the_file() {
    contained("  exit(3);", "your file's interpreter ended");
    // What it prints, a forged reply included, goes nowhere: the call answers what the
    // function returns.
    contained(
        "  for k = 1:3000, fputs(stdout, \"{\\\"output\\\": [[1, 0], [0, 1]]}\\n\"); end; \
         fdisp(stdout, 1); Sigma_delta = 'mine';",
        "\"mine\"",
    );
    // Clearing everything, the harness's own functions included, clears the student's.
    contained(
        "  clear all; Sigma_delta = diag([k_r * abs(ds_r), k_l * abs(ds_l)]) + 1;",
        "wheel_noise",
    );
}

#[test]
fn a_missing_function_is_named_with_its_matlab_declaration() {
    let source = ODOMETRY
        .correct
        .replace("= wheel_noise(", "= wheel_noises(");
    let result = grade(Exercise::Odometry, &source);
    let test = result
        .tests
        .iter()
        .find(|t| t.subject == Subject::Function("wheel_noise".to_owned()))
        .expect("a test of wheel_noise");
    assert!(
        test.message.contains(
            "wheel_noise is not defined: declare it at top level, as function ... = wheel_noise(...)"
        ),
        "{}",
        test.message
    );
}

#[test]
fn errors_name_the_line_of_the_students_file() {
    // The EKF file's functions end with `end`; the sensor-fusion file's do not, and is
    // split into a file a function: both count lines as the student's file does.
    for (exercise, source, function) in [
        (Exercise::Odometry, ODOMETRY.correct, "wheel_noise"),
        (
            Exercise::SensorFusion,
            SENSOR_FUSION.correct,
            "heading_sigma",
        ),
    ] {
        let (at, line) = source
            .lines()
            .enumerate()
            .find(|(_, line)| {
                line.starts_with("function ") && line.contains(&format!(" {function}("))
            })
            .unwrap();
        let broken = source.replacen(line, &format!("{line}\n  [1 2] * [3 4];"), 1);
        let result = grade(exercise, &broken);
        let test = result
            .tests
            .iter()
            .find(|t| t.subject == Subject::Function(function.to_owned()))
            .unwrap();
        let expected = format!(
            "operator *: nonconformant arguments (op1 is 1x2, op2 is 1x2) (line {})",
            at + 2
        );
        assert!(test.message.contains(&expected), "{}", test.message);
    }
    // A syntax error names its line too.
    let broken = ODOMETRY
        .correct
        .replacen("Sigma_delta = diag(", "Sigma_delta = diag((", 1);
    let result = grade(Exercise::Odometry, &broken);
    let line = ODOMETRY
        .correct
        .lines()
        .position(|l| l.contains("Sigma_delta = diag("))
        .unwrap()
        + 1;
    assert!(
        result.tests.iter().all(|t| t
            .message
            .contains(&format!("parse error near line {line} of odometry.m"))),
        "{:?}",
        result.tests.iter().map(|t| &t.message).collect::<Vec<_>>()
    );
}

#[test]
fn hints_speak_matlab() {
    contained(
        "  Sigma_delta = [k_r * abs(ds_r), k_l * abs(ds_l)];",
        "`Sigma_delta` should be a 2 x 2 matrix, but is a 1 x 2 matrix.",
    );
    let source = EKF_LOCALIZATION.correct.replace(
        "z_hat = [hypot(dx, dy); wrap(atan2(dy, dx) - x(3))];",
        "z_hat = [hypot(dx, dy); atan2(dy, dx) - x(3)];",
    );
    let result = grade(Exercise::EkfLocalization, &source);
    let test = result
        .tests
        .iter()
        .find(|t| t.subject == Subject::Function("observation_model".to_owned()))
        .unwrap();
    assert!(
        test.message
            .contains("with mod, whose result takes the sign of 2 pi")
            && !test.message.contains("JavaScript"),
        "{}",
        test.message
    );
}
