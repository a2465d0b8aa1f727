//! Validation (issue 6): the paper's Table IV with Quince, the slope limit, skid steering and
//! the paper's Figs. 2 and 3, all through `tracksim::validate::run_validation` (one call; the
//! cases run in parallel on the machine's cores).

use std::path::{Path, PathBuf};
use tracksim::Method as TrackMethod;
use tracksim::validate::{ValidationOptions, ValidationReport, run_validation_with};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Table IV in the paper's order (0 deg: 40, 120, 190 mm; 45 deg: 120, 240, 380 mm): the real
/// robot and the paper's simulation.
const TABLE_IV_PAPER: [&str; 6] = ["S", "S", "F", "S", "S", "F"];

/// What this simulator gets with grousers and rigid contact (no slop). The 0 deg / 120 mm case
/// differs for a geometric reason (VALIDATION.md): the step's corner is 29 mm above the
/// sub-track's front pulley centre and 4.5 mm outside the circle the grouser tips sweep when
/// the pulley presses against the riser, so the grousers only rub the vertical face, and
/// friction on that face (at most mu^2 / (1 + mu^2) = 26 % of the weight) cannot lift the
/// front. The paper's ODE contacts let grousers sink up to 10 mm (`min_depth`), enough to reach
/// the corner: with that slop the table matches the paper (asserted below).
const TABLE_IV_RIGID: [&str; 6] = ["S", "F", "F", "S", "S", "F"];

fn report() -> ValidationReport {
    {
        // The no-grouser column is reported by `tracksim validate` but not asserted; leaving
        // it out saves a third of the test's time.
        let opts = ValidationOptions {
            without_grousers: false,
            rigid_contact: true,
            // Reported by `tracksim validate`; its asserted cases are in
            // tests/suite/issue_11_compliance.rs.
            compliant_grousers: false,
            ..Default::default()
        };
        let r = run_validation_with(&root(), TrackMethod::Okada2020, opts, |line| {
            eprintln!("{line}")
        })
        .expect("validation runs");
        eprintln!("{}", r.to_markdown());
        r
    }
}

#[test]
fn validation_cases() {
    let r = &report();

    // Table IV with grousers and the paper simulator's contact slop: the paper's table.
    let got: Vec<&str> = r
        .table_iv
        .iter()
        .map(|c| c.with_grousers.result.as_str())
        .collect();
    assert_eq!(got, TABLE_IV_PAPER, "Table IV with grousers, contact slop");
    let reality: Vec<&str> = r.table_iv.iter().map(|c| c.reality.as_str()).collect();
    assert_eq!(reality, TABLE_IV_PAPER);
    // With rigid contact the 0 deg / 120 mm case fails (see TABLE_IV_RIGID).
    let rigid: Vec<&str> = r
        .table_iv
        .iter()
        .map(|c| {
            c.with_grousers_rigid
                .as_ref()
                .expect("rigid column run")
                .result
                .as_str()
        })
        .collect();
    assert_eq!(
        rigid, TABLE_IV_RIGID,
        "Table IV with grousers, rigid contact"
    );
    // The slop is what the paper's simulator allowed, and the grousers do use it at the step
    // (they press into the riser: measured 8-17 mm) but not beyond the 16 mm grouser height
    // plus the few mm a loaded edge adds even with rigid contact (up to 14 mm there): a
    // deeper figure would mean the belt itself went into the step.
    for c in &r.table_iv {
        let sank = c.with_grousers.max_penetration_mm;
        assert!(sank < 20.0, "{}: grousers sank {sank} mm", c.name);
    }

    // Slope limit, turning, paper figures.
    for c in &r.cases {
        assert!(
            c.passed,
            "{} / {}: measured {}, expected {}",
            c.group, c.name, c.measured, c.expected
        );
    }
    assert!(r.cases.iter().any(|c| c.group == "slope"));
    assert_eq!(r.cases.iter().filter(|c| c.group == "turning").count(), 2);
    // Deformable soil (issue 30): sinkage, drawbar pull-slip, grousers, slope, multi-pass.
    assert_eq!(r.cases.iter().filter(|c| c.group == "soil").count(), 5);
    let highest = r
        .slope_runs
        .iter()
        .filter(|s| s.climbed)
        .map(|s| s.angle_deg)
        .fold(f64::NAN, f64::max);
    assert!(
        (highest - 30.96).abs() <= 2.0,
        "steepest slope climbed {highest}"
    );

    // The report's own verdict agrees.
    assert!(r.table_iv.iter().all(|c| c.passed));
    assert!(r.passed());

    // Markdown, JSON and one plot per case.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("validation");
    let written = r.write(&dir).expect("report written");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("Table IV") && md.contains("| 45 deg | 240 mm |"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(json["table_iv"].as_array().unwrap().len(), 6);
    for c in &r.table_iv {
        assert!(
            written.contains(&dir.join(format!("{}.png", c.plot))),
            "{}",
            c.plot
        );
        assert!(dir.join(format!("{}.svg", c.plot)).is_file());
    }
    for c in r.cases.iter().filter(|c| !c.plot.is_empty()) {
        assert!(dir.join(format!("{}.png", c.plot)).is_file(), "{}", c.plot);
    }
}

/// The whole validation as `tracksim validate --out out/validate` runs it (with the no-grouser
/// column), written to `out/validate`: `cargo test -p tracksim --test suite validation:: -- --ignored`.
#[test]
#[ignore]
fn full_report() {
    let r = tracksim::validate::run_validation(&root(), TrackMethod::Okada2020, |line| {
        eprintln!("{line}")
    })
    .expect("validation runs");
    r.write(&root().join("out/validate")).expect("written");
    println!("{}", r.to_markdown());
}
