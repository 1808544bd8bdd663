//! `spreadlight accuracy post` at a small size: every effect and setting gets
//! a row with its GPU time and its error against the brute-force reference,
//! and the quality pins trade error the way the tables say (FXAA at any
//! quality is nearer the supersampled image than no FXAA, more motion-blur
//! samples are nearer the many-views reference, half-resolution DOF is
//! further from it than full).

mod support;

use support::{spreadlight, text};

struct Row {
    effect: String,
    setting: String,
    rmse: f64,
    ssim: f64,
    ms: Option<f64>,
}

fn rows() -> Vec<Row> {
    let o = spreadlight(&[
        "accuracy",
        "post",
        "--views",
        "16",
        "--taa-frames",
        "4",
        "--error-size",
        "96x54",
        "--time-size",
        "32x18",
        "--warmup",
        "0",
        "--frames",
        "1",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    text(&o.stdout)
        .lines()
        .map(|line| {
            let v: serde_json::Value = serde_json::from_str(line).expect("a JSON row");
            Row {
                effect: v["effect"].as_str().expect("effect").to_owned(),
                setting: v["setting"].as_str().expect("setting").to_owned(),
                rmse: v["rmse"].as_f64().expect("rmse"),
                ssim: v["ssim"].as_f64().expect("ssim"),
                ms: v["ms"].as_f64(),
            }
        })
        .collect()
}

#[test]
fn every_post_effect_is_timed_and_its_quality_trades_error_as_stated() {
    let rows = rows();
    let of = |effect: &str| rows.iter().filter(|r| r.effect == effect).count();
    // DOF: 4 sample counts at Full and Half; motion blur 4; TAA 3; FXAA off and 3.
    assert_eq!(
        [of("DOF"), of("MotionBlur"), of("TAA"), of("FXAA")],
        [8, 4, 3, 4]
    );
    for r in &rows {
        let what = format!("{} {}", r.effect, r.setting);
        assert!(r.rmse > 0.0 && r.rmse < 0.2, "{what}: RMSE {}", r.rmse);
        assert!(r.ssim > 0.5 && r.ssim <= 1.0, "{what}: SSIM {}", r.ssim);
        // The test adapter has timestamps: every setting is timed (FXAA off runs no pass).
        let ms = r.ms.unwrap_or_else(|| panic!("{what}: untimed"));
        match r.setting.starts_with("off") {
            true => assert_eq!(ms, 0.0, "{what}"),
            false => assert!(ms > 0.0, "{what}: {ms}"),
        }
    }
    let rmse = |effect: &str, setting: &str| {
        rows.iter()
            .find(|r| r.effect == effect && r.setting == setting)
            .unwrap_or_else(|| panic!("no {effect} {setting}"))
            .rmse
    };
    let off = rmse("FXAA", "off (one sample)");
    for quality in ["Low", "Medium", "High"] {
        assert!(rmse("FXAA", quality) < off, "FXAA {quality}");
    }
    assert!(rmse("MotionBlur", "25 samples") < rmse("MotionBlur", "5 samples"));
    for samples in [8, 16, 32, 64] {
        let full = rmse("DOF", &format!("{samples} samples"));
        let half = rmse("DOF", &format!("{samples} samples, half"));
        assert!(
            half > full,
            "DOF {samples}: half {half} against full {full}"
        );
    }
}
