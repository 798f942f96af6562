//! MRCLAM data set 6 as published (robots 1 to 3, read from the shared data): every record
//! of every file is read, the first and last as the files hold them, and every reading
//! names a barcode of the room; on the 50 Hz grid, with the noise learned from each
//! robot's own recording, the three filters localize each robot to about 20 cm where its
//! commands alone drift metres away, and every one of them is overconfident.

use labs::mrclam::format::{parse_robot, parse_world};
use labs::mrclam::grid::Run;
use labs::mrclam::motion::Noise;
use labs::mrclam::run::{self, CONSISTENT_INSIDE, Consistency, Kind, Settings};
use labs::mrclam::{FIRST_POST, Measurement, Odometry, Pose, Post, Robot, World, learn};

testdata::data_tests!(
    the_room_has_fifteen_posts_and_twenty_barcodes,
    every_record_of_each_robot_is_read_in_order,
    every_reading_names_a_subject_of_the_room,
    the_noise_learned_from_each_robot_is_of_the_camera_and_wheels_we_know,
    the_filters_localize_each_robot_where_its_commands_drift_away,
);

const DIR: &str = "mrclam/MRCLAM_Dataset6";

fn world() -> World {
    let posts = format!("{DIR}/Landmark_Groundtruth.dat");
    let barcodes = format!("{DIR}/Barcodes.dat");
    parse_world(
        (&testdata::read(&posts), &posts),
        (&testdata::read(&barcodes), &barcodes),
    )
    .unwrap()
}

/// Robot `n`'s three files, and how many lines of each hold a record (neither blank nor a
/// comment), counted here on their own.
fn robot(n: u32) -> (Robot, [usize; 3]) {
    let names =
        ["Odometry", "Measurement", "Groundtruth"].map(|kind| format!("{DIR}/Robot{n}_{kind}.dat"));
    let texts = names.clone().map(|name| testdata::read(&name));
    let records = texts.clone().map(|text| {
        text.lines()
            .filter(|line| !line.trim().is_empty() && !line.starts_with('#'))
            .count()
    });
    let robot = parse_robot(
        (&texts[0], &names[0]),
        (&texts[1], &names[1]),
        (&texts[2], &names[2]),
    )
    .unwrap();
    (robot, records)
}

fn the_room_has_fifteen_posts_and_twenty_barcodes() {
    let world = world();
    let subjects: Vec<u32> = world.posts.iter().map(|post| post.subject).collect();
    assert_eq!(subjects, (FIRST_POST..=20).collect::<Vec<_>>());
    assert_eq!(
        world.posts[0],
        Post {
            subject: 6,
            x: 0.58831396,
            y: -4.28264845,
            sd_x: 0.0000457,
            sd_y: 0.00027395
        }
    );
    assert_eq!(world.barcodes.len(), 20);
    assert_eq!(world.subject_of(5), Some(1));
    assert_eq!(world.subject_of(14), Some(2));
    assert_eq!(
        world.post_of(25).map(|post| (post.x, post.y)),
        Some((1.24712229, 4.46500471))
    );
    // The room is 15 x 8 m or so: every post within it.
    for post in &world.posts {
        assert!(post.x.abs() < 8.0 && post.y.abs() < 5.0, "{post:?}");
    }
}

fn every_record_of_each_robot_is_read_in_order() {
    let (one, records) = robot(1);
    assert_eq!(
        [one.odometry.len(), one.measurements.len(), one.truth.len()],
        records
    );
    assert_eq!(records, [61_785, 1_942, 49_241]);
    assert_eq!(
        one.odometry[0],
        Odometry {
            t: 1248444187.156,
            v: 0.086,
            omega: -0.398
        }
    );
    assert_eq!(
        one.odometry.last(),
        Some(&Odometry {
            t: 1248445075.103,
            v: 0.0,
            omega: 0.0
        })
    );
    assert_eq!(
        one.measurements[0],
        Measurement {
            t: 1248444189.599,
            barcode: 14,
            range: 3.787,
            bearing: -0.257
        }
    );
    assert_eq!(
        one.truth.last(),
        Some(&Pose {
            t: 1248444946.976,
            x: 3.7738052,
            y: 2.9741189,
            theta: 0.4345
        })
    );
    // Ground truth for about 770 s of the run, odometry for about 890.
    let span = |first: f64, last: f64| last - first;
    assert!((span(one.truth[0].t, one.truth.last().unwrap().t) - 771.9).abs() < 0.1);
    assert!((span(one.odometry[0].t, one.odometry.last().unwrap().t) - 887.9).abs() < 0.1);
    for n in [2, 3] {
        let (robot, records) = robot(n);
        assert_eq!(
            [
                robot.odometry.len(),
                robot.measurements.len(),
                robot.truth.len()
            ],
            records,
            "robot {n}"
        );
    }
}

/// Every reading names a barcode of the room but three, as published: robot 1 once saw a
/// barcode 43 and robot 3 twice a 34, which no subject wears (misreadings a filter skips).
fn every_reading_names_a_subject_of_the_room() {
    let world = world();
    let mut unknown = Vec::new();
    for n in 1..=3 {
        let (robot, _) = robot(n);
        let mut of_posts = 0;
        for reading in &robot.measurements {
            assert!(
                reading.range > 0.0 && reading.bearing.abs() <= std::f64::consts::PI,
                "robot {n}: {reading:?}"
            );
            match world.subject_of(reading.barcode) {
                None => unknown.push((n, reading.barcode)),
                Some(subject) => {
                    assert!(subject != n, "robot {n} reads its own barcode: {reading:?}");
                    if subject >= FIRST_POST {
                        of_posts += 1;
                    }
                }
            }
        }
        // Most readings are of posts; the rest, of the other robots.
        assert!(
            2 * of_posts > robot.measurements.len(),
            "robot {n}: {of_posts}"
        );
    }
    assert_eq!(unknown, [(1, 43), (3, 34), (3, 34)]);
}

/// Robot `n` on the grid, and the noise learned from its recording.
fn learned(n: u32) -> (Run, Noise) {
    let world = world();
    let (robot, _) = robot(n);
    let run = Run::new(&robot, &world).unwrap();
    let noise = learn::noise(&robot, &world, &run).unwrap();
    (run, noise)
}

/// About 770 s for robot 1 and 900 s for the others, at 50 Hz; the readings of posts on
/// the grid; alphas of tens of per cent (the truth's own jitter, differenced at 50 Hz,
/// is in them), a range error of 10 to 20 cm and a bearing error of a degree or a few.
fn the_noise_learned_from_each_robot_is_of_the_camera_and_wheels_we_know() {
    for (n, steps, posts) in [(1, 38_594, 1_534), (2, 45_001, 3_239), (3, 45_001, 4_348)] {
        let (run, noise) = learned(n);
        assert_eq!(run.steps.len(), steps, "robot {n}");
        let read: usize = run.steps.iter().map(|step| step.readings.len()).sum();
        assert_eq!(read, posts, "robot {n}");
        let [a1, a2, a3, a4] = noise.alphas;
        assert!(
            (0.3..0.5).contains(&a1) && (0.0..0.1).contains(&a2),
            "robot {n}: {noise:?}"
        );
        assert!(
            (1.4..1.9).contains(&a3) && (0.2..0.5).contains(&a4),
            "robot {n}: {noise:?}"
        );
        let range = noise.measurement[(0, 0)].sqrt();
        let bearing = noise.measurement[(1, 1)].sqrt();
        assert!((0.1..0.2).contains(&range), "robot {n}: range sd {range}");
        assert!(
            (0.01..0.1).contains(&bearing),
            "robot {n}: bearing sd {bearing}"
        );
    }
}

/// The figures the issue measured with NumPy (EKF, UKF, particle filter; robots 1 to 3):
/// ours, with the choices of `labs::mrclam` (commands averaged over each step, R2 by
/// maximum likelihood with zero mean, the UKF's alpha = kappa = 1), are within 10 % of
/// them or better.
const ISSUE_RMS: [[f64; 3]; 3] = [
    [0.194, 0.226, 0.215],
    [0.191, 0.223, 0.213],
    [0.186, 0.222, 0.209],
];

fn the_filters_localize_each_robot_where_its_commands_drift_away() {
    for n in 1..=3u32 {
        let (run, noise) = learned(n);
        let drift = run::drift(&run);
        assert!(
            (2.5..4.5).contains(&drift.rms),
            "robot {n}: dead reckoning {drift:?}"
        );
        let settings = Settings {
            seed: u64::from(n),
            ..Settings::default()
        };
        for (i, kind) in Kind::ALL.into_iter().enumerate() {
            let name = kind.name();
            let mut filter = run::make(kind, &run, &noise, &settings);
            let (beliefs, readings) = run::filter(&run, filter.as_mut());
            let c = Consistency::of(&run, &beliefs);
            let issue = ISSUE_RMS[i][n as usize - 1];
            assert!(
                c.errors.rms <= 1.1 * issue && c.errors.rms > 0.7 * issue,
                "robot {n}, {name}: RMS {:.3} m against {issue} m",
                c.errors.rms
            );
            assert!(c.errors.rms < drift.rms / 10.0, "robot {n}, {name}");
            // Overconfident: the truth far less often inside the 3-sigma ellipse than a
            // consistent filter's 98.9 %, the NEES far above its 3.
            assert!(
                c.inside_three_sigma < 0.7 * CONSISTENT_INSIDE,
                "robot {n}, {name}: {c:?}"
            );
            assert!(c.nees > 10.0, "robot {n}, {name}: {c:?}");
            // The gate turns away one reading in ten or fewer.
            assert!(
                readings.used > 8 * readings.rejected,
                "robot {n}, {name}: {readings:?}"
            );
        }
    }
}
