//! `estlab odometry`: dead reckoning along a path, how its covariance grows, and (on
//! request) many robots whose wheels really slip, systematic errors and the UMBmark test.

use super::{numbers, print, short};
use crate::error::Error;
use labs::odometry::{
    Direction, MonteCarlo, MonteCarloParams, OdometryParams, Propagation, Shape, SystematicErrors,
    SystematicRun, Umbmark, UmbmarkParams, monte_carlo, propagate, systematic, umbmark,
};
use serde::Serialize;

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum ShapeName {
    Line,
    Circle,
    Square,
    FigureEight,
    Polyline,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Turn {
    /// clockwise
    Cw,
    /// counter-clockwise
    Ccw,
}

/// Propagate a differential-drive robot's odometry and its covariance along a path
/// (defaults: a 4 m square, counter-clockwise, 5 cm per step, wheel base 0.35 m,
/// k_r = k_l = 1e-4 m, a start known exactly).
#[derive(clap::Args)]
pub struct Args {
    /// The path's shape (default: square, or polyline with --points).
    #[arg(long, value_enum)]
    shape: Option<ShapeName>,
    /// The line's length, the circle's or figure eight's radius, the square's side, metres
    /// (default 4, 2, 1.5 and 4).
    #[arg(long)]
    size: Option<f64>,
    /// Which way the circle or square goes round (default: counter-clockwise).
    #[arg(long, value_enum)]
    direction: Option<Turn>,
    /// The polyline's points, x,y;x,y;... (quote them for the shell).
    #[arg(long, value_parser = points, allow_hyphen_values = true)]
    points: Option<Points>,
    /// Metres per step (the most the robot's centre moves in a step).
    #[arg(long)]
    speed: Option<f64>,
    /// b, the distance between the wheels, metres.
    #[arg(long)]
    wheel_base: Option<f64>,
    /// k_r, the right wheel's distance variance per metre rolled, metres.
    #[arg(long)]
    k_r: Option<f64>,
    /// k_l, the left wheel's distance variance per metre rolled, metres.
    #[arg(long)]
    k_l: Option<f64>,
    /// Diagonal of the start's covariance: x,y,theta (variances).
    #[arg(long, value_parser = numbers::<3>)]
    sigma0: Option<[f64; 3]>,
    /// Also simulate N robots whose wheels slip with the noise the odometry assumes.
    #[arg(long, value_name = "N")]
    monte_carlo: Option<usize>,
    /// The seed of the Monte Carlo robots and of the UMBmark runs.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The real robot's wheel diameter ratio E_d = D_r / D_l (prints its true path's end).
    #[arg(long)]
    e_d: Option<f64>,
    /// The real wheel base over the one the odometry assumes, E_b.
    #[arg(long)]
    e_b: Option<f64>,
    /// Run the UMBmark test on a square of this side (metres; 4 when no value is given),
    /// with E_d, E_b and the wheel noise.
    #[arg(long, value_name = "SIDE", num_args = 0..=1, default_missing_value = "4")]
    umbmark: Option<f64>,
    /// UMBmark runs in each direction (default 5).
    #[arg(long, requires = "umbmark")]
    runs: Option<usize>,
    /// Print everything as JSON: the parameters, every step's pose and covariance, and
    /// the Monte Carlo, systematic and UMBmark results asked for.
    #[arg(long)]
    json: bool,
}

/// A polyline's points (a type of its own: clap would take a `Vec` for a repeated flag).
#[derive(Clone, Debug)]
struct Points(Vec<[f64; 2]>);

/// `x,y;x,y;...`
fn points(text: &str) -> Result<Points, String> {
    text.split(';')
        .filter(|pair| !pair.trim().is_empty())
        .map(numbers::<2>)
        .collect::<Result<_, _>>()
        .map(Points)
}

fn params(args: &Args) -> Result<OdometryParams, Error> {
    let d = OdometryParams::default();
    let name = match (args.shape, &args.points) {
        (None, Some(_)) => ShapeName::Polyline,
        (None, None) => ShapeName::Square,
        (Some(ShapeName::Polyline), _) | (Some(_), None) => args.shape.unwrap(),
        (Some(_), Some(_)) => {
            return Err(Error::Invalid(
                "--points: only a polyline has points (--shape polyline)".into(),
            ));
        }
    };
    let goes_round = matches!(name, ShapeName::Circle | ShapeName::Square);
    if args.direction.is_some() && !goes_round {
        return Err(Error::Invalid(
            "--direction: only a circle or a square goes round one way or the other".into(),
        ));
    }
    if args.size.is_some() && name == ShapeName::Polyline {
        return Err(Error::Invalid(
            "--size: a polyline's size is its points (--points)".into(),
        ));
    }
    let direction = match args.direction.unwrap_or(Turn::Ccw) {
        Turn::Cw => Direction::Clockwise,
        Turn::Ccw => Direction::CounterClockwise,
    };
    let size = |default: f64| args.size.unwrap_or(default);
    let shape = match name {
        ShapeName::Line => Shape::Line { length: size(4.0) },
        ShapeName::Circle => Shape::Circle {
            radius: size(2.0),
            direction,
        },
        ShapeName::Square => Shape::Square {
            side: size(4.0),
            direction,
        },
        ShapeName::FigureEight => Shape::FigureEight { radius: size(1.5) },
        ShapeName::Polyline => Shape::Polyline {
            points: args.points.clone().map(|p| p.0).unwrap_or_default(),
        },
    };
    let [x, y, theta] = args.sigma0.unwrap_or([0.0; 3]);
    Ok(OdometryParams {
        shape,
        speed: args.speed.unwrap_or(d.speed),
        wheel_base: args.wheel_base.unwrap_or(d.wheel_base),
        k_r: args.k_r.unwrap_or(d.k_r),
        k_l: args.k_l.unwrap_or(d.k_l),
        sigma0: [[x, 0.0, 0.0], [0.0, y, 0.0], [0.0, 0.0, theta]],
    })
}

/// A setting as `short` writes it, zero as 0.
fn setting(value: f64) -> String {
    if value == 0.0 {
        "0".to_owned()
    } else {
        short(value)
    }
}

fn triple(v: &[f64; 3]) -> String {
    format!("({:.6}, {:.6}, {:.6})", v[0], v[1], v[2])
}

fn row(v: &[f64; 3]) -> String {
    format!("({:.6e}, {:.6e}, {:.6e})", v[0], v[1], v[2])
}

/// What `--json` prints: the settings, the propagation, and what else was asked for.
#[derive(Serialize)]
struct Report<'a> {
    params: &'a OdometryParams,
    propagation: &'a Propagation,
    #[serde(skip_serializing_if = "Option::is_none")]
    monte_carlo: Option<&'a MonteCarlo>,
    #[serde(skip_serializing_if = "Option::is_none")]
    systematic: Option<SystematicReport<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    umbmark: Option<UmbmarkReport<'a>>,
}

#[derive(Serialize)]
struct SystematicReport<'a> {
    errors: &'a SystematicErrors,
    run: &'a SystematicRun,
}

#[derive(Serialize)]
struct UmbmarkReport<'a> {
    errors: &'a SystematicErrors,
    test: &'a UmbmarkParams,
    result: &'a Umbmark,
}

pub fn run(args: &Args) -> Result<(), Error> {
    let params = params(args)?;
    let propagation = propagate(&params)?;
    let errors = SystematicErrors {
        e_d: args.e_d.unwrap_or(1.0),
        e_b: args.e_b.unwrap_or(1.0),
    };
    let monte_carlo = args
        .monte_carlo
        .map(|robots| {
            monte_carlo(
                &params,
                &MonteCarloParams {
                    robots,
                    seed: args.seed,
                    cloud_every: 0,
                },
            )
        })
        .transpose()?;
    let systematic = (args.e_d.is_some() || args.e_b.is_some())
        .then(|| systematic(&params, &errors))
        .transpose()?;
    let umbmark_test = args.umbmark.map(|side| UmbmarkParams {
        side,
        runs: args.runs.unwrap_or(5),
        seed: args.seed,
    });
    let umbmark = umbmark_test
        .as_ref()
        .map(|test| umbmark(&params, &errors, test))
        .transpose()?;

    if args.json {
        let report = Report {
            params: &params,
            propagation: &propagation,
            monte_carlo: monte_carlo.as_ref(),
            systematic: systematic.as_ref().map(|run| SystematicReport {
                errors: &errors,
                run,
            }),
            umbmark: umbmark_test
                .as_ref()
                .zip(umbmark.as_ref())
                .map(|(test, result)| UmbmarkReport {
                    errors: &errors,
                    test,
                    result,
                }),
        };
        return print(&serde_json::to_string(&report).expect("reports serialise"));
    }

    let mut lines = vec![
        format!(
            "odometry: {}, {} steps of at most {} m, wheel base {} m",
            params.shape.describe(),
            propagation.path.steps(),
            params.speed,
            params.wheel_base
        ),
        format!(
            "wheel noise: k_r = {} m, k_l = {} m; start covariance diag({}, {}, {})",
            setting(params.k_r),
            setting(params.k_l),
            setting(params.sigma0[0][0]),
            setting(params.sigma0[1][1]),
            setting(params.sigma0[2][2])
        ),
    ];
    let pose = propagation.final_pose();
    let sigma = propagation.final_covariance();
    lines.push(format!("final pose (x, y, theta): {}", triple(&pose)));
    lines.push(format!(
        "final std (x, y, theta): {}",
        triple(&[0, 1, 2].map(|i| sigma[i][i].sqrt()))
    ));
    for (name, r) in ["x", "y", "theta"].iter().zip(&sigma) {
        lines.push(format!("final covariance, row {name}: {}", row(r)));
    }
    if let Some(mc) = &monte_carlo {
        lines.push(format!(
            "monte carlo: {} robots, seed {}",
            mc.robots, args.seed
        ));
        lines.push(format!(
            "sample mean (x, y, theta): {}",
            triple(&mc.sample_mean)
        ));
        for (name, r) in ["x", "y", "theta"].iter().zip(&mc.sample_covariance) {
            lines.push(format!("sample covariance, row {name}: {}", row(r)));
        }
        lines.push(match mc.inside_3_sigma {
            Some(share) => format!(
                "inside the 3-sigma ellipse: {:.2} % of the robots (a Gaussian: {:.2} %)",
                100.0 * share,
                100.0 * mc.gaussian_inside_3_sigma
            ),
            None => "inside the 3-sigma ellipse: no ellipse, the position covariance is singular"
                .to_owned(),
        });
    }
    if let Some(run) = &systematic {
        lines.push(format!(
            "systematic errors: E_d = {}, E_b = {}",
            errors.e_d, errors.e_b
        ));
        lines.push(format!(
            "true final pose (x, y, theta): {}",
            triple(run.truth.last().expect("a path starts somewhere"))
        ));
        lines.push(format!(
            "error, true - odometry (x, y, theta): {}",
            triple(&run.final_error)
        ));
    }
    if let (Some(test), Some(result)) = (&umbmark_test, &umbmark) {
        lines.push(format!(
            "UMBmark: square of side {} m, {} runs each way, E_d = {}, E_b = {}, seed {}",
            test.side, test.runs, errors.e_d, errors.e_b, test.seed
        ));
        for (name, direction) in [
            ("clockwise", &result.clockwise),
            ("counter-clockwise", &result.counter_clockwise),
        ] {
            lines.push(format!(
                "{name}: centre of gravity (x, y) ({:.6}, {:.6}), r = {:.6} m",
                direction.centre[0], direction.centre[1], direction.r
            ));
        }
        lines.push(format!("E_max,syst = {:.6} m", result.e_max_syst));
    }
    print(&lines.join("\n"))
}
