//! What a grading of the exercise consists of, from a seed: the test cases of every
//! student function (see [`crate::grading::planned_cases`]), a UKF run and a particle
//! filter run over robots of a data set generated from the seed (from the server's hidden
//! seed on the server), with the reference filters' beliefs along them, and the job the
//! JavaScript harness carries out with the student's code.

use super::UkfParticle;
use super::contract::{Call, RESAMPLE_BELOW, pairs};
use super::generate::generate;
use super::grade::grade;
use super::job::{FilterRecord, FilterRun, FilterStepData, PostReading, RunFilter};
use crate::Exercise;
use crate::exercises::Graded;
use crate::grading::{
    ExercisePlan, GradeResult, Hidden, Job, Outputs, PlannedCase, RunPhase, function_phases,
    planned_cases, rows,
};
use crate::mrclam::belief::{Belief, Filter};
use crate::mrclam::grid::{Control, Run, Step};
use crate::mrclam::learn;
use crate::mrclam::motion::Noise;
use crate::mrclam::particle::{self, Draws, ParticleFilter};
use crate::mrclam::run::{self as runs, start};
use crate::mrclam::sensor::{self, GATE};
use crate::mrclam::simulate::{self, DatasetParams};
use crate::mrclam::ukf::Ukf;
use crate::mrclam::{Robot, World};
use crate::rng::Rng;
use nalgebra::Vector2;
use std::collections::VecDeque;

/// How long the student's code may take over one whole run of the loop.
pub const RUN_LIMIT_MS: u32 = 10_000;

/// The functions the loop calls over a UKF run, and over a particle filter run.
pub const UKF_FUNCTIONS: [&str; 5] = [
    "measurement_noise",
    "learn_alphas",
    "process_noise",
    "ukf_predict",
    "ukf_update",
];
pub const PARTICLE_FUNCTIONS: [&str; 7] = [
    "measurement_noise",
    "learn_alphas",
    "sample_motion",
    "particle_weights",
    "needs_resampling",
    "low_variance_resample",
    "particle_estimate",
];

/// The runs' grid: every `COARSER` steps of the data set's 50 Hz grid made one, 10 Hz.
const COARSER: usize = 5;
/// The steps of a UKF run (a minute at 10 Hz) and of a particle filter run (half a
/// minute), and the particle filter's particles: what Octave gets through well within
/// the run's limit.
pub const UKF_STEPS: usize = 600;
pub const PARTICLE_STEPS: usize = 300;
pub const PARTICLES: usize = 30;

/// The part of a seed's random numbers the runs are drawn from (ASCII "runs").
const RUNS: u64 = 0x7275_6e73;

/// Everything one grading checks, made from the student's seed (and, on the server, a
/// seed of hidden cases).
#[derive(Clone, Debug)]
pub struct Plan {
    pub seed: u64,
    /// The seed of the hidden cases and runs, known to the server only.
    pub hidden: Option<u64>,
    pub cases: Vec<PlannedCase<Call>>,
    pub runs: Vec<FilterSpec>,
}

/// A run of the loop with the student's functions.
#[derive(Clone, Debug)]
pub struct FilterSpec {
    /// `ukf`, `particle-filter`.
    pub name: String,
    pub run: FilterRun,
    /// The time at every step, seconds from the start, and the true pose there.
    pub times: Vec<f64>,
    pub truth: Vec<[f64; 3]>,
    /// The reference filter's belief at the start and after every step.
    pub reference: FilterRecord,
}

impl Plan {
    /// The public suite, the variant of `seed`, and a data set of two robots drawn from
    /// `seed` (from `hidden` instead when there is one, as on the server): the UKF runs
    /// along the first robot's recording, the particle filter along the second's.
    pub fn new(seed: u64, hidden: Option<Hidden>) -> Plan {
        let cases = hidden.map(|h| h.cases);
        let mut rng = Rng::substream(cases.unwrap_or(seed), RUNS);
        let (robots, world, learned) = teaching_data_set(|| (rng.uniform() * 1e9) as u64);
        let residuals: Vec<[f64; 2]> = learn::residuals(&robots[0], &world)
            .iter()
            .map(|r| [r.x, r.y])
            .collect();
        Plan {
            seed,
            hidden: cases,
            cases: planned_cases(generate, seed, cases),
            runs: vec![
                FilterSpec::ukf(&learned[0], &residuals),
                FilterSpec::particle(&learned[1], &residuals, &mut rng),
            ],
        }
    }

    pub fn run(&self, name: &str) -> Option<&FilterSpec> {
        self.runs.iter().find(|run| run.name == name)
    }
}

/// A data set of two robots of the seed `draw` gives, each with what its recording
/// teaches. A robot that saw too few posts in its minute to learn the camera's noise
/// (about one in 1,200) has its data set drawn again, of the next seed: every plan has one.
fn teaching_data_set(mut draw: impl FnMut() -> u64) -> (Vec<Robot>, World, Vec<learn::Learned>) {
    loop {
        let params = DatasetParams {
            seed: draw(),
            robots: 2,
            duration: 60.0,
            ..DatasetParams::default()
        };
        let (robots, world) = simulate::generate(&params).expect("the drawn data sets are valid");
        let learned: Result<Vec<learn::Learned>, _> = robots
            .iter()
            .map(|robot| learn::Learned::new(robot, &world))
            .collect();
        if let Ok(learned) = learned {
            return (robots, world, learned);
        }
    }
}

impl ExercisePlan for Plan {
    fn exercise(&self) -> Exercise {
        Exercise::UkfParticle
    }

    fn seed(&self) -> u64 {
        self.seed
    }

    /// What the harness needs to call the student's code: the arguments of every case (not
    /// the expected outputs) and the commands, readings and draws of every run (not the
    /// truth or the reference's beliefs).
    fn job(&self) -> Job {
        Job {
            functions: function_phases(&self.cases),
            runs: self.runs.iter().map(FilterSpec::job).collect(),
        }
    }

    fn grade(&self, outputs: &Outputs) -> GradeResult {
        grade(self, outputs)
    }
}

/// The random numbers the particle filter draws, handed to it as the run gives them.
#[derive(Clone, Debug, Default)]
struct Replay {
    normals: VecDeque<f64>,
    uniform: Option<f64>,
}

impl Draws for Replay {
    fn normal(&mut self) -> f64 {
        self.normals
            .pop_front()
            .expect("the run gives a normal draw for each")
    }

    fn uniform(&mut self) -> f64 {
        self.uniform
            .take()
            .expect("the run gives each step's offset")
    }
}

/// A standard normal draw to 4 decimals, as the job carries it (the reference draws the
/// same number the loop reads).
fn drawn(rng: &mut Rng) -> f64 {
    libm::round(rng.standard_normal() * 1e4) / 1e4
}

impl FilterSpec {
    /// The UKF along the first `UKF_STEPS` of `learned`'s run, with the camera's noise
    /// learned from `residuals`.
    fn ukf(learned: &learn::Learned, residuals: &[[f64; 2]]) -> FilterSpec {
        let (run, noise, taught) = prepared(learned, residuals, UKF_STEPS);
        let mut filter = Ukf::new(start(&run), noise);
        let (beliefs, _) = runs::filter(&run, &mut filter);
        FilterSpec::new(
            "ukf",
            RunFilter::Ukf,
            &run,
            noise,
            taught,
            None,
            Vec::new(),
            &beliefs,
        )
    }

    /// The particle filter of `PARTICLES` along the first `PARTICLE_STEPS` of `learned`'s
    /// run, with every draw taken from `rng` and given to the loop.
    fn particle(learned: &learn::Learned, residuals: &[[f64; 2]], rng: &mut Rng) -> FilterSpec {
        let (run, noise, taught) = prepared(learned, residuals, PARTICLE_STEPS);
        let settings = particle::Settings {
            particles: PARTICLES,
            resample_below: RESAMPLE_BELOW,
            gate: f64::INFINITY,
        };
        let first = Replay {
            normals: (0..3 * PARTICLES).map(|_| drawn(rng)).collect(),
            uniform: None,
        };
        let mut filter = ParticleFilter::new(start(&run), noise, settings, first);
        let cloud: Vec<[f64; 3]> = filter.samples().iter().map(|&p| p.into()).collect();
        let mut beliefs = vec![filter.belief()];
        let mut draws = Vec::with_capacity(run.steps.len());
        for step in &run.steps[1..] {
            let moving = step.control.v != 0.0 || step.control.omega != 0.0;
            let normals: Option<Vec<[f64; 2]>> =
                moving.then(|| (0..PARTICLES).map(|_| [drawn(rng), drawn(rng)]).collect());
            let r = rng.uniform();
            let replay = filter.draws_mut();
            replay.normals = normals.iter().flatten().flatten().copied().collect();
            replay.uniform = Some(r);
            filter.predict(step.control, run.dt);
            filter.update(&step.readings);
            beliefs.push(filter.belief());
            draws.push((normals, r));
        }
        FilterSpec::new(
            "particle-filter",
            RunFilter::Particle,
            &run,
            noise,
            taught,
            Some(cloud),
            draws,
            &beliefs,
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn new(
        name: &str,
        filter: RunFilter,
        run: &Run,
        noise: Noise,
        taught: Taught,
        particles: Option<Vec<[f64; 3]>>,
        draws: Vec<(Option<Vec<[f64; 2]>>, f64)>,
        beliefs: &[Belief],
    ) -> FilterSpec {
        let begin = start(run);
        let steps = run.steps[1..]
            .iter()
            .enumerate()
            .map(|(k, step)| {
                let (normals, r) = draws.get(k).cloned().unzip();
                FilterStepData {
                    u: [step.control.v, step.control.omega],
                    readings: step
                        .readings
                        .iter()
                        .map(|reading| PostReading {
                            z: sensor::observed(reading).into(),
                            landmark: reading.landmark.into(),
                        })
                        .collect(),
                    normals: normals.flatten(),
                    r,
                }
            })
            .collect();
        FilterSpec {
            name: name.to_owned(),
            run: FilterRun {
                filter,
                dt: run.dt,
                commanded: taught.commanded,
                implied: taught.implied,
                residuals: taught.residuals,
                gate: GATE,
                start: begin.mean.into(),
                start_sigma: rows(&begin.covariance),
                particles,
                steps,
            },
            times: run.steps.iter().map(|s| s.t).collect(),
            truth: run.steps.iter().map(|s| s.truth.into()).collect(),
            reference: FilterRecord {
                q: Some(rows(&noise.measurement)),
                alphas: Some(noise.alphas),
                poses: beliefs.iter().map(|b| b.mean.into()).collect(),
                covariances: beliefs.iter().map(|b| rows(&b.covariance)).collect(),
            },
        }
    }

    /// The steps of the run.
    pub fn steps(&self) -> usize {
        self.truth.len()
    }

    fn job(&self) -> RunPhase {
        let functions: &[&str] = match self.run.filter {
            RunFilter::Ukf => &UKF_FUNCTIONS,
            RunFilter::Particle => &PARTICLE_FUNCTIONS,
        };
        RunPhase::new(
            UkfParticle::DECLARATION.run_loop,
            &self.name,
            functions,
            RUN_LIMIT_MS,
            &self.run,
        )
    }
}

/// What the loop learns the noise from, as the job gives it: the camera's residuals, and
/// the commands over the run's span on the data's grid beside the motion the truth implies
/// (to a millionth, as the reference learns from them too).
struct Taught {
    residuals: Vec<[f64; 2]>,
    commanded: Vec<[f64; 2]>,
    implied: Vec<[f64; 2]>,
}

/// The first `steps` of `learned`'s run on the coarser grid, its noise as the loop learns
/// it (the alphas from the commands and the implied motion over the run's span, the
/// camera's from `residuals`), and what that is learned from.
fn prepared(
    learned: &learn::Learned,
    residuals: &[[f64; 2]],
    steps: usize,
) -> (Run, Noise, Taught) {
    let run = coarser(&learned.run, steps);
    let mut fine = learned.run.clone();
    fine.steps.truncate(COARSER * (steps - 1) + 1);
    let millionth = |x: f64| libm::round(x * 1e6) / 1e6;
    let (commanded, implied): (Vec<[f64; 2]>, Vec<[f64; 2]>) = learn::implied_controls(&fine)
        .iter()
        .map(|(u, m)| {
            (
                [millionth(u.v), millionth(u.omega)],
                [millionth(m.v), millionth(m.omega)],
            )
        })
        .unzip();
    let vectors: Vec<Vector2<f64>> = residuals.iter().map(|&r| r.into()).collect();
    let noise = Noise {
        alphas: learn::alphas(&pairs(&commanded, &implied)),
        measurement: learn::measurement(&vectors).expect("a generated camera's residuals"),
    };
    let taught = Taught {
        residuals: residuals.to_vec(),
        commanded,
        implied,
    };
    (run, noise, taught)
}

/// The first `steps` of `run` on a grid `COARSER` times coarser: each step's command the
/// mean of those it spans (what was commanded during it on average), its readings all of
/// theirs, its truth and time those at its end.
fn coarser(run: &Run, steps: usize) -> Run {
    let mut coarse = vec![run.steps[0].clone()];
    for fine in run.steps[1..].chunks_exact(COARSER).take(steps - 1) {
        let last = &fine[COARSER - 1];
        let mean = |part: fn(&Step) -> f64| fine.iter().map(part).sum::<f64>() / COARSER as f64;
        coarse.push(Step {
            t: last.t,
            control: Control {
                v: mean(|s| s.control.v),
                omega: mean(|s| s.control.omega),
            },
            readings: fine
                .iter()
                .flat_map(|s| s.readings.iter().copied())
                .collect(),
            truth: last.truth,
        });
    }
    Run {
        dt: run.dt * COARSER as f64,
        steps: coarse,
        skipped: run.skipped,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A data set whose robot saw too few posts to teach (of seed 24036369 the second saw
    /// none in its minute) is drawn again, of the next seed.
    #[test]
    fn a_robot_that_cannot_teach_has_its_data_set_drawn_again() {
        let mut seeds = [24_036_369, 7].into_iter();
        let (robots, _, learned) = teaching_data_set(|| seeds.next().expect("a seed"));
        assert_eq!(seeds.next(), None, "not drawn again");
        assert_eq!(learned.len(), 2);
        assert!(robots.iter().all(|robot| !robot.measurements.is_empty()));
    }

    /// The runs are as long as planned, read posts, move the cloud and resample it; plans
    /// of different seeds differ, and the job carries no truth.
    #[test]
    fn the_runs_read_posts_and_resample() {
        for seed in 1..=10 {
            let plan = Plan::new(seed, None);
            let [ukf, particle] = [&plan.runs[0], &plan.runs[1]];
            assert_eq!(ukf.steps(), UKF_STEPS);
            assert_eq!(particle.steps(), PARTICLE_STEPS);
            for spec in &plan.runs {
                let read: usize = spec.run.steps.iter().map(|s| s.readings.len()).sum();
                assert!(read > 20, "seed {seed}, {}: {read} readings", spec.name);
                assert_eq!(spec.reference.poses.len(), spec.steps());
            }
            let moving = particle.run.steps.iter().filter(|s| s.normals.is_some());
            assert!(moving.count() > PARTICLE_STEPS / 2);
        }
        assert_ne!(
            Plan::new(1, None).runs[0].truth,
            Plan::new(2, None).runs[0].truth
        );
        let job = serde_json::to_string(&Plan::new(1, None).job()).unwrap();
        assert!(!job.contains("truth"));
    }
}
