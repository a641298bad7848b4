//! Results a new user saw exit 0 while wrong, each now a correct result or a refusal naming the
//! value and its valid range: a law whose arithmetic overflows for the pair, a kind named
//! wrongly, friction with an enormous stiffness, LAMMPS's short names of rolling and twisting
//! laws in a scene.

mod common;

use common::{fails, ok_json, scene, sh};

/// `dashpot ARGS` with every plugin of the workspace (rolling and twisting laws included).
fn with_all(args: &[&str]) -> std::process::Output {
    common::dashpot_with(common::all_plugins_dir(), args)
}

/// LSD with k = 1e308 N/m: √(k/m) overflows, so w0 and γ were printed as inf and the contact time as
/// NaN with exit 0. Refused, naming the coefficient, k and the largest k this pair allows; a k
/// just below that bound evaluates with finite coefficients, one just above is refused.
#[test]
fn eval_refuses_a_law_whose_coefficients_overflow_and_names_the_bound() {
    let args = sh("eval --law lsd --set k=1e308 --delta 1e-6 --rate 0.1");
    fails(
        &args,
        &[
            "w0 = inf",
            "is not finite",
            "k = 1e308",
            "(0, inf)",
            "k must be at most",
        ],
    );
    let o = common::dashpot(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    let bound: f64 = err
        .split("at most ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no bound in: {err}"));
    assert!(bound > 1e200 && bound < 1e308, "{bound}");
    let v = ok_json(&sh(&format!(
        "eval --law lsd --set k={:e} --delta 1e-6 --rate 0.1 --json",
        bound * 0.99
    )));
    for (name, c) in v["coefficients"].as_object().unwrap() {
        assert!(c.as_f64().is_some_and(f64::is_finite), "{name} = {c}");
    }
    fails(
        &sh(&format!(
            "eval --law lsd --set k={:e} --delta 1e-6 --rate 0.1",
            bound * 1.01
        )),
        &["is not finite"],
    );
    // an ordinary stiffness: τ = π/√(k/m − γ²) as before
    let v = ok_json(&sh("eval --law lsd --set k=1e6 --delta 1e-6 --rate 0.1 --json"));
    let c = &v["coefficients"];
    let (w0, g) = (c["w0"].as_f64().unwrap(), c["gamma"].as_f64().unwrap());
    let tau = std::f64::consts::PI / (w0 * w0 - g * g).sqrt();
    assert!((c["contact_time"].as_f64().unwrap() / tau - 1.0).abs() < 1e-12);
}

/// A law of another kind named to `calibrate` is named by its own kind.
#[test]
fn calibrate_names_the_kind_of_a_law_that_is_not_a_contact_law() {
    fails(
        &sh("calibrate --law mindlin --restitution 0.5"),
        &["'mindlin' is a tangential law", "contact (normal) law"],
    );
    fails(
        &sh("calibrate --law mcnamara-falcon --restitution 0.5"),
        &["'mcnamara-falcon' is a restitution law"],
    );
}

/// A contact time so short that LSD's closed-form stiffness overflows is refused naming k and
/// its range (the C ABI refuses it the same way, through the registry).
#[test]
fn calibrate_refuses_a_closed_form_out_of_range() {
    fails(
        &sh("calibrate --law lsd --restitution 0.5 --contact-time 1e-300"),
        &["k = inf", "(0, inf)"],
    );
}

/// Friction with a huge spring stiffness: the spring saturates at once and the contact slides
/// at the Coulomb cap the whole time, so kt = 1e200 N/m and kt = 1e100 N/m give the same
/// tangential velocity (it was 0.5, friction lost, when the stiffness overflowed), and it is the
/// sliding value below the impact's 0.5 m/s.
#[test]
fn friction_with_an_enormous_stiffness_still_caps_at_coulomb() {
    let vt = |kt: &str| {
        let v = ok_json(&sh(&format!(
            "collide --law hsd --tangential linear-history --angle 30 --set kt={kt} --json"
        )));
        v["tangential_velocity_out"]
            .as_f64()
            .unwrap_or_else(|| panic!("no tangential velocity in {v}"))
    };
    let (a, b) = (vt("1e200"), vt("1e100"));
    assert!((a - b).abs() < 1e-9, "kt = 1e200: {a}, kt = 1e100: {b}");
    assert!((a - 0.357).abs() < 5e-4, "{a}");
}

/// In a scene's [rolling] and [twisting] tables LAMMPS's short names (`sds`, `epsd`,
/// `marshall`) mean the laws `pair_style dashpot` reads them as, and the run reports the full
/// names; a name that is no law's is still refused.
#[test]
fn a_scene_takes_lammps_short_names_of_rolling_and_twisting_laws() {
    let text = |rolling: &str, twisting: &str| {
        format!(
            "dimension = 3\ngravity = [0.0, 0.0, -9.81]\nduration = 0.002\n\
             [law]\nname = \"hsd\"\nparams = {{ eps = 0.5 }}\n\
             [tangential]\nname = \"mindlin\"\nparams = {{ mu = 0.3 }}\n\
             [rolling]\nname = \"{rolling}\"\n[twisting]\nname = \"{twisting}\"\n\
             [material]\nyoung = 1.0e7\npoisson = 0.3\ndensity = 2500.0\n\
             [[particle]]\nposition = [0.0, 0.0, 0.005]\nvelocity = [0.1, 0.0, 0.0]\ndiameter = 0.01\n\
             [[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n"
        )
    };
    for (rolling, twisting, long_r, long_t) in [
        ("sds", "marshall", "rolling-sds", "twisting-marshall"),
        ("epsd", "sds", "rolling-epsd", "twisting-sds"),
        ("rolling-sds", "twisting-sds", "rolling-sds", "twisting-sds"),
    ] {
        let p = scene(
            &format!("short-{rolling}-{twisting}.toml"),
            &text(rolling, twisting),
        );
        let o = with_all(&["dem", "--scene", p.to_str().unwrap(), "--json"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{rolling}/{twisting}: {err}");
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(
            out.contains(&format!("\"{long_r}\"")) && out.contains(&format!("\"{long_t}\"")),
            "{rolling}/{twisting}: {out}"
        );
    }
    let p = scene("short-bad.toml", &text("nonesuch", "marshall"));
    let o = with_all(&["dem", "--scene", p.to_str().unwrap(), "--json"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("'nonesuch'"));
}
