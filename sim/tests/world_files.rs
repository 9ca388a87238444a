//! The simulator's world expresses real fields: plot layouts, rows and hedges
//! along rounded polylines, posts and fences, plants and centre lines read
//! from CSV files (errors naming file, line and column), plots joined by a
//! Dubins path. Each test fails if the world were built wrong.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic
)]

use std::path::{Path, PathBuf};

use fieldguide_sim::rng::SimRng;
use fieldguide_sim::scenario::{Setup, Source};
use fieldguide_sim::world::PlantKind;
use fieldguide_sim::ScenarioError;

fn stress(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios/stress")
        .join(name)
}

fn setup_of(source: &Source) -> Result<Setup, ScenarioError> {
    source.setup(&mut SimRng::from_seed(1))
}

fn stress_source(name: &str) -> Source {
    Source::resolve(stress(name).to_str().unwrap()).unwrap()
}

/// A folder of its own under the system's temporary folder, holding `files`.
fn folder(test: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fieldguide-world-files-{test}"));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    dir
}

/// The stress scenario `name` with `edit` applied, read from `dir`.
fn edited(name: &str, dir: &Path, edit: impl Fn(String) -> String) -> Source {
    let text = std::fs::read_to_string(stress(name)).unwrap();
    Source {
        origin: "edited.toml".to_owned(),
        text: edit(text),
        base_dir: Some(dir.to_path_buf()),
    }
}

#[test]
fn rows_along_a_polyline_keep_their_layout_about_the_curved_centre_line() {
    let setup = setup_of(&stress_source("rows-polyline-maize.toml")).unwrap();
    let plot = &setup.world.plots[0].spec;
    assert_eq!(plot.rows, 2);
    // The polyline's length: two corners of 30 m radius cut from 25 + 21.54 + 25 m.
    let turn = (8.0_f64 / 20.0).atan();
    let tangent = 30.0 * (turn / 2.0).tan();
    let expected = 25.0 + 20.0_f64.hypot(8.0) + 25.0 - 4.0 * tangent + 2.0 * 30.0 * turn;
    assert!((plot.length - expected).abs() < 1e-9, "{}", plot.length);
    let crops: Vec<_> = setup
        .world
        .plants
        .iter()
        .filter(|p| p.kind == PlantKind::Crop)
        .collect();
    let (mut left, mut right) = (0, 0);
    for p in &crops {
        let q = plot
            .project(p.position.x(), p.position.y())
            .expect("every plant lies beside its plot");
        // Rows 0.8 m apart: ±0.4 m, scattered at most 5 cm.
        assert!((q.lateral.abs() - 0.4).abs() <= 0.05 + 1e-9, "{q:?}");
        if q.lateral > 0.0 {
            left += 1;
        } else {
            right += 1;
        }
    }
    // A plant every 0.25 m, 5 % missing: about 280 a row.
    for n in [left, right] {
        assert!((240..320).contains(&n), "{left} {right}");
    }
    let mean = |f: &dyn Fn(&&fieldguide_sim::world::Plant) -> f64| {
        crops.iter().map(f).sum::<f64>() / crops.len() as f64
    };
    assert!((mean(&|p| p.height) - 0.6).abs() < 0.01);
    assert!((mean(&|p| p.radius) - 0.04).abs() < 0.003);
    // Round the second corner the rows head north-east then east again.
    let (_, _, h) = plot.centre_line(plot.length / 2.0);
    assert!((h - turn).abs() < 1e-9);
}

#[test]
fn layout_fields_replace_the_crops_values_and_are_checked() {
    let dir = folder("layout", &[]);
    let three = edited("rows-polyline-dubins.toml", &dir, |t| {
        t.replacen(
            "length_m = 25.0\n",
            "length_m = 25.0\nrows = 3\nrow_spacing_m = 0.5\n",
            1,
        )
    });
    let setup = setup_of(&three).unwrap();
    let plot = &setup.world.plots[0].spec;
    assert_eq!((plot.rows, plot.row_spacing), (3, 0.5));
    for target in [-0.5, 0.0, 0.5] {
        let n = setup
            .world
            .plants
            .iter()
            .filter(|p| p.position.x() < 25.0 && (p.position.y() - target).abs() < 0.1)
            .count();
        assert!(n > 100, "row at {target}: {n}");
    }
    let merged = edited("rows-polyline-dubins.toml", &dir, |t| {
        t.replacen(
            "length_m = 25.0\n",
            "length_m = 25.0\nrow_spacing_m = 0.08\n",
            1,
        )
    });
    let e = setup_of(&merged).unwrap_err();
    assert_eq!(e.field(), Some("world.plots[0].row_spacing_m"), "{e}");
}

#[test]
fn a_polyline_that_folds_back_or_whose_rows_cross_is_refused_at_its_vertex() {
    let dir = folder("fold", &[]);
    let with_centre = |centre: &'static str, radius: &'static str| {
        edited("rows-polyline-maize.toml", &dir, move |t| {
            t.replace(
                "centre = [[0.0, 0.0], [25.0, 0.0], [45.0, 8.0], [70.0, 8.0]]",
                centre,
            )
            .replace("corner_radius_m = 30.0", radius)
        })
    };
    let e = setup_of(&with_centre(
        "centre = [[0.0, 0.0], [25.0, 0.0], [5.0, 2.0]]",
        "corner_radius_m = 1.0",
    ))
    .unwrap_err();
    assert_eq!(e.field(), Some("world.plots[0].centre[1]"), "{e}");
    assert!(e.to_string().contains("folds back"), "{e}");
    // A 0.3 m corner is narrower than the band of rows (0.44 m each side).
    let e = setup_of(&with_centre(
        "centre = [[0.0, 0.0], [25.0, 0.0], [45.0, 8.0]]",
        "corner_radius_m = 0.3",
    ))
    .unwrap_err();
    assert_eq!(e.field(), Some("world.plots[0].centre[1]"), "{e}");
    assert!(e.to_string().contains("cross"), "{e}");
}

#[test]
fn trunks_and_fences_stand_where_the_file_puts_them_and_the_lidar_sees_them() {
    let setup = setup_of(&stress_source("trunks-posts-hedge.toml")).unwrap();
    let obstacles = &setup.world.obstacles;
    // Trunks: every 1.5 m along 19.16 m from (52, 9.91), numbers 3 and 7 missing.
    let (a, b) = ([52.0, 9.91], [70.0, 16.46]);
    let length = f64::hypot(b[0] - a[0], b[1] - a[1]);
    let u = [(b[0] - a[0]) / length, (b[1] - a[1]) / length];
    let trunks: Vec<_> = obstacles
        .circles
        .iter()
        .filter(|c| (c.radius - 0.1).abs() < 1e-12)
        .collect();
    let count = (length / 1.5).floor() as usize + 1;
    assert_eq!(trunks.len(), count - 2);
    let mut numbers: Vec<usize> = trunks
        .iter()
        .map(|c| {
            let along = (c.center[0] - a[0]) * u[0] + (c.center[1] - a[1]) * u[1];
            let k = (along / 1.5).round();
            assert!((along - 1.5 * k).abs() < 1e-9, "{along}");
            k as usize
        })
        .collect();
    numbers.sort_unstable();
    assert!(!numbers.contains(&3) && !numbers.contains(&7));
    // The wire fence: posts every 3 m on y = −4, nothing between them; the
    // boards: a wall between their posts.
    let probe = |x: f64| obstacles.cast_brute([x, 0.0], [0.0, -1.0], 10.0);
    let at_post = probe(22.0).unwrap();
    assert!((at_post - 3.95).abs() < 1e-9, "{at_post}");
    assert_eq!(probe(23.5), None, "a ray between the wire's posts passes");
    let boards_at = |x: f64| -4.0 + (x - 40.0) * (7.28 / 20.0);
    let d = obstacles
        .cast_brute([51.0, 10.0], [0.0, -1.0], 30.0)
        .unwrap();
    assert!((d - (10.0 - boards_at(51.0))).abs() < 1e-6, "{d}");
}

const PLANTS: &str =
    "x_m,y_m,radius_m,height_m,kind\n-5.0,2.0,0.05,0.5,crop\n-4.75,2.0,0.05,0.5,grass\n";

/// The error of the CSV field scenario with the files `files` (the three
/// good CSV files unless replaced).
fn csv_error(test: &str, files: &[(&str, &str)]) -> ScenarioError {
    let centre = std::fs::read_to_string(stress("field-csv-centre.csv")).unwrap();
    let posts = std::fs::read_to_string(stress("field-csv-posts.csv")).unwrap();
    let mut all = vec![
        ("field-csv-plants.csv", PLANTS),
        ("field-csv-centre.csv", centre.as_str()),
        ("field-csv-posts.csv", posts.as_str()),
    ];
    all.extend_from_slice(files);
    let dir = folder(test, &all);
    setup_of(&edited("field-csv-maize.toml", &dir, |t| t)).expect_err("must be refused")
}

#[test]
fn csv_errors_name_the_file_line_and_column() {
    let e = csv_error(
        "missing-column",
        &[("field-csv-plants.csv", "x_m,y_m,radius_m\n1,2,0.05\n")],
    );
    assert_eq!(e.cell(), Some(("field-csv-plants.csv", 1, 4)), "{e}");
    assert!(e.to_string().contains("missing column `height_m`"), "{e}");
    let e = csv_error(
        "non-numeric",
        &[(
            "field-csv-plants.csv",
            "x_m,y_m,radius_m,height_m\n# stems\n-5,2,0.05,0.5\n-4,2,0.05,tall\n",
        )],
    );
    assert_eq!(e.cell(), Some(("field-csv-plants.csv", 4, 4)), "{e}");
    assert!(
        e.to_string().contains("`tall` is not a finite number"),
        "{e}"
    );
    let e = csv_error(
        "duplicate",
        &[(
            "field-csv-plants.csv",
            "x_m,y_m,radius_m,height_m\n-5,2,0.05,0.5\n-4,2,0.05,0.5\n-5.0002,2,0.05,0.5\n",
        )],
    );
    assert_eq!(e.cell(), Some(("field-csv-plants.csv", 4, 1)), "{e}");
    assert!(
        e.to_string()
            .contains("duplicate plant: the stem of line 2"),
        "{e}"
    );
    // The robot starts at O = (−6, −0.15) heading east, 2 m wheelbase, 1.5 m track.
    let e = csv_error(
        "under-robot",
        &[(
            "field-csv-plants.csv",
            "x_m,y_m,radius_m,height_m,kind\n-5.5,0.3,0.02,0.1,grass\n-5.0,0.3,0.05,0.5,crop\n",
        )],
    );
    assert_eq!(e.cell(), Some(("field-csv-plants.csv", 3, 1)), "{e}");
    assert!(e.to_string().contains("under the robot"), "{e}");
    let e = csv_error(
        "kind",
        &[(
            "field-csv-plants.csv",
            "x_m,y_m,radius_m,height_m,kind\n-5,2,0.05,0.5,tree\n",
        )],
    );
    assert_eq!(e.cell(), Some(("field-csv-plants.csv", 2, 5)), "{e}");
    // A surveyed centre line coming back across itself: the rows would cross.
    let e = csv_error(
        "crossing",
        &[(
            "field-csv-centre.csv",
            "x_m,y_m\n0,0\n60,0\n60,50\n20,50\n20,0.5\n",
        )],
    );
    assert_eq!(e.field(), Some("world.plots[0].centre_csv"), "{e}");
    assert_eq!(e.cell(), Some(("field-csv-centre.csv", 2, 1)), "{e}");
    assert!(e.to_string().contains("cross"), "{e}");
    let e = csv_error(
        "posts",
        &[("field-csv-posts.csv", "x_m,y_m,radius_m\n0,-3,0.1\n5,-3\n")],
    );
    assert_eq!(e.cell(), Some(("field-csv-posts.csv", 3, 3)), "{e}");
    // A missing file is a read error naming it, never a run on an empty field.
    let dir = folder("no-file", &[]);
    let e = setup_of(&edited("field-csv-maize.toml", &dir, |t| {
        t.replace("field-csv-centre.csv", "nowhere.csv")
    }))
    .unwrap_err();
    assert!(e.to_string().contains("nowhere.csv"), "{e}");
}

#[test]
fn the_csv_field_is_read_as_written() {
    let setup = setup_of(&stress_source("field-csv-maize.toml")).unwrap();
    let from_file: Vec<_> = setup
        .world
        .plants
        .iter()
        .filter(|p| (p.position.y() - 2.0).abs() < 1e-12 || (p.position.y() - 1.6).abs() < 1e-12)
        .collect();
    assert_eq!(from_file.len(), 21 + 8);
    assert_eq!(
        from_file
            .iter()
            .filter(|p| p.kind == PlantKind::Grass)
            .count(),
        8
    );
    // The plot's centre line passes through the surveyed end points.
    let plot = &setup.world.plots[0].spec;
    let (x, y, _) = plot.centre_line(plot.length);
    assert!((x - 60.0).abs() < 1e-9 && (y - 3.0).abs() < 1e-9);
    let posts = &setup.world.obstacles.circles;
    assert_eq!(posts.len(), 13);
    assert!((posts[3].radius - 0.12).abs() < 1e-12 && (posts[4].radius - 0.08).abs() < 1e-12);
}

/// The largest heading change between consecutive waypoint segments of the path, rad.
fn largest_kink(setup: &Setup) -> f64 {
    let v = setup.path.vertices();
    let headings: Vec<f64> = v
        .windows(2)
        .map(|w| {
            (w[1].position.y() - w[0].position.y()).atan2(w[1].position.x() - w[0].position.x())
        })
        .collect();
    headings
        .windows(2)
        .map(|h| (h[1] - h[0]).abs())
        .fold(0.0, f64::max)
}

#[test]
fn a_dubins_join_has_a_continuous_heading_where_a_straight_one_kinks() {
    let dir = folder("join", &[]);
    let quiet = |t: String| t.replace("recording_noise_m = 0.005", "recording_noise_m = 0.0");
    let dubins = setup_of(&edited("rows-polyline-dubins.toml", &dir, quiet)).unwrap();
    // 0.1 m samples on a 6 m radius turn by at most 0.1 / 6 rad each.
    let kink = largest_kink(&dubins);
    assert!(kink <= 0.1 / 6.0 + 1e-6, "{kink}");
    let straight = setup_of(&edited("rows-polyline-dubins.toml", &dir, |t| {
        quiet(t).replace(", join = \"dubins\", turning_radius_m = 6.0", "")
    }))
    .unwrap();
    // The straight join from (25, 0) to (40, 3): a kink of atan(3 / 15).
    let kink = largest_kink(&straight);
    assert!((kink - (3.0_f64 / 15.0).atan()).abs() < 0.01, "{kink}");
    // A join that would loop (the next plot too close for the radius) is refused.
    let e = setup_of(&edited("rows-polyline-dubins.toml", &dir, |t| {
        t.replace("x_m = 40.0, y_m = 3.0", "x_m = 32.0, y_m = 3.0")
    }))
    .unwrap_err();
    assert_eq!(e.field(), Some("world.plots[1].start"), "{e}");
    assert!(e.to_string().contains("loop"), "{e}");
}
