//! Names in words (`results::names`): every published key number of every scene and every
//! parameter of every scene has one, without a code spelling.
#![cfg(feature = "plots")]

use impacting_cantilever::results::names::{self, parameters};
use impacting_cantilever::results::scene::Resolution;

/// Every published key number of every scene has a name without a code spelling, and no
/// two keys of a scene share a name.
#[test]
fn every_published_key_number_has_a_name_in_words() {
    let published = impacting_cantilever::results::diff::published().expect("published numbers");
    assert!(published.len() >= 15, "{} scenes", published.len());
    let mut failures = Vec::new();
    for s in &published {
        let mut seen = std::collections::HashMap::new();
        for (key, _) in &s.numbers.0 {
            let n = names::name(&s.scene, key);
            if let Some(code) = names::code_spelling(&n) {
                failures.push(format!("{} / {key}: \"{n}\" keeps {code:?}", s.scene));
            }
            if let Some(other) = seen.insert(n.clone(), key.clone()) {
                failures.push(format!("{} / {key} and {other}: both \"{n}\"", s.scene));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} names:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
#[test]
fn every_parameter_of_every_scene_has_words() {
    for spec in impacting_cantilever::results::scenes::all() {
        for resolution in [Resolution::Book, Resolution::Test] {
            let (lines, missing) = parameters::in_words(spec.name(), &spec.params_json(resolution));
            assert!(missing.is_empty(), "{}: {missing:?}", spec.name());
            assert!(!lines.is_empty(), "{}", spec.name());
            for l in &lines {
                assert!(
                    !l.contains('_')
                        || l.contains("r_E")
                        || l.contains("r_e")
                        || l.contains("A_free"),
                    "{}: {l}",
                    spec.name()
                );
            }
        }
    }
}

#[test]
fn a_range_and_units_read_as_written() {
    let p = serde_json::json!({"k_over_k1_range": [1.0, 10000.0], "zeta1": 0.01,
        "omega_over_w1": 2.0, "transient": 1000});
    let (lines, missing) = parameters::in_words("fig5", &p);
    assert!(missing.is_empty());
    assert_eq!(
        lines,
        [
            "stop stiffness k from 1k₁ to 10⁴k₁",
            "modal damping ratio ζ₁: 0.01",
            "forcing frequency ω: 2(β₁⁻)²",
            "periods discarded: 1000"
        ]
    );
}
