//! Unit tests of `config::live`: steps, shown values, switches, cycling, number format.

use super::*;

fn store_with(values: &[(&'static str, &str)], observed: &[(&'static str, f64)]) -> Store {
    let mut s = Store::default();
    for (k, v) in values {
        s.values.insert(k, Some(v.to_string()));
    }
    for (k, v) in observed {
        s.observed.insert(k, *v);
    }
    s
}

#[test]
fn every_live_key_is_an_option() {
    for k in LIVE_KEYS {
        assert!(options::find(k.name).is_some(), "{}", k.name);
    }
}

#[test]
fn steps_scale_from_the_value_in_force() {
    let s = store_with(&[], &[("depthiness", 0.08), ("convergence", 10.0)]);
    let d = s
        .next_value(key("depthiness").unwrap(), &Action::Step("depthiness", 1))
        .unwrap();
    assert_eq!(d, "0.1");
    let c = s
        .next_value(key("convergence").unwrap(), &Action::Step("convergence", -1))
        .unwrap();
    assert_eq!(c, format_number(10.0 / 1.1));
    let f = s.next_value(key("focus").unwrap(), &Action::Step("focus", -1)).unwrap();
    assert_eq!(f, "-0.008");
}

#[test]
fn a_set_value_wins_over_the_observed_one_and_auto_shows_both() {
    let s = store_with(&[("convergence", "auto")], &[("convergence", 12.5)]);
    assert_eq!(s.shown("convergence"), "auto (12.5)");
    assert_eq!(s.number("convergence"), Some(12.5));
    let s = store_with(&[("depthiness", "0.3")], &[("depthiness", 0.1)]);
    assert_eq!(
        (s.shown("depthiness"), s.number("depthiness")),
        ("0.3".into(), Some(0.3))
    );
    assert_eq!(
        store_with(&[], &[("depthiness", 0.1)]).shown("depthiness"),
        "0.1 (default)"
    );
}

#[test]
fn switches_remember_their_last_on_value() {
    let k = LiveKey {
        name: "slot",
        kind: Kind::Switch("on"),
    };
    let mut s = Store::default();
    assert_eq!(s.next_value(&k, &Action::Next("slot")).unwrap(), "on");
    s.values.insert("slot", Some("0.7".into()));
    assert_eq!(s.next_value(&k, &Action::Next("slot")).unwrap(), "off");
    s.switched.insert("slot", "0.7".into());
    s.values.insert("slot", Some("off".into()));
    assert_eq!(s.next_value(&k, &Action::Next("slot")).unwrap(), "0.7");
}

#[test]
fn cycling_skips_what_is_not_possible() {
    // No device in the test process's settings: native is skipped.
    assert_eq!(cycle(&["quilt", "native", "sbs"], Some("quilt")), "sbs");
    assert_eq!(cycle(&["quilt", "native", "sbs"], Some("sbs")), "quilt");
    assert_eq!(cycle(&["quilt", "sbs"], None), "quilt");
}

#[test]
fn numbers_read_back_short() {
    assert_eq!(format_number(0.1), "0.1");
    assert_eq!(format_number(12.3456), "12.35");
    assert_eq!(format_number(0.000123456), "0.0001235");
    assert_eq!(format_number(-2.0), "-2");
    assert_eq!(format_number(f64::NAN), "0");
}
