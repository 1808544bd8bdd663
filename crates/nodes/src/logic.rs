//! Logic and comparison: `=`, `!=`, `<`, `>`, `<=`, `>=` (values and
//! strings), `AND`, `OR`, `XOR`, `NOT` and their spectral forms over a whole
//! spread. The nodes that watch a signal over frames (`Change`, `TogEdge`,
//! `FlipFlop`, `Toggle`, `Counter`, `MonoFlop`) are in `logic/signals.rs`.

pub mod signals;

use spreadlight_graph::{NodeDef, Registry};

const CATEGORY: &str = "Logic";

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "= (Value)",
            CATEGORY,
            "True where Input 1 and Input 2 differ by at most Epsilon, slice by slice.",
        )
        .input("Input 1", 0.0f32)
        .input("Input 2", 0.0f32)
        .input("Epsilon", 0.0f32)
        .output::<bool>("Output")
        .per_slice3(|a: &f32, b: &f32, e: &f32| (a - b).abs() <= e.abs()),
    );
    r.add(
        NodeDef::new(
            "!= (Value)",
            CATEGORY,
            "True where Input 1 and Input 2 differ by more than Epsilon, slice by slice.",
        )
        .input("Input 1", 0.0f32)
        .input("Input 2", 0.0f32)
        .input("Epsilon", 0.0f32)
        .output::<bool>("Output")
        .per_slice3(|a: &f32, b: &f32, e: &f32| (a - b).abs() > e.abs()),
    );
    r.add(compare(
        "< (Value)",
        "True where Input 1 < Input 2.",
        |a, b| a < b,
    ));
    r.add(compare(
        "> (Value)",
        "True where Input 1 > Input 2.",
        |a, b| a > b,
    ));
    r.add(compare(
        "<= (Value)",
        "True where Input 1 <= Input 2.",
        |a, b| a <= b,
    ));
    r.add(compare(
        ">= (Value)",
        "True where Input 1 >= Input 2.",
        |a, b| a >= b,
    ));
    r.add(
        NodeDef::new(
            "= (String)",
            CATEGORY,
            "True where Input 1 and Input 2 are the same text, slice by slice; Case Sensitive \
             off compares them ignoring case.",
        )
        .input("Input 1", String::new())
        .input("Input 2", String::new())
        .input("Case Sensitive", true)
        .output::<bool>("Output")
        .per_slice3(|a: &String, b: &String, case: &bool| same_text(a, b, *case)),
    );
    r.add(
        NodeDef::new(
            "!= (String)",
            CATEGORY,
            "True where Input 1 and Input 2 are different texts, slice by slice; Case Sensitive \
             off compares them ignoring case.",
        )
        .input("Input 1", String::new())
        .input("Input 2", String::new())
        .input("Case Sensitive", true)
        .output::<bool>("Output")
        .per_slice3(|a: &String, b: &String, case: &bool| !same_text(a, b, *case)),
    );
    r.add(boolean(
        "AND (Boolean)",
        "Input 1 and Input 2, slice by slice.",
        |a, b| a && b,
    ));
    r.add(boolean(
        "OR (Boolean)",
        "Input 1 or Input 2, slice by slice.",
        |a, b| a || b,
    ));
    r.add(boolean(
        "XOR (Boolean)",
        "True where exactly one of Input 1 and Input 2 is, slice by slice.",
        |a, b| a != b,
    ));
    r.add(
        NodeDef::new(
            "NOT (Boolean)",
            CATEGORY,
            "The opposite of Input, slice by slice.",
        )
        .input("Input", false)
        .output::<bool>("Output")
        .per_slice1(|a: &bool| !a),
    );
    r.add(spectral(
        "AND (Boolean Spectral)",
        "True when every slice of Input is (and for an empty Input, as the empty AND is).",
        |v| v.iter().all(|&b| b),
    ));
    r.add(spectral(
        "OR (Boolean Spectral)",
        "True when any slice of Input is (false for an empty Input).",
        |v| v.iter().any(|&b| b),
    ));
    signals::register(r);
}

fn same_text(a: &str, b: &str, case_sensitive: bool) -> bool {
    if case_sensitive {
        a == b
    } else {
        a.to_lowercase() == b.to_lowercase()
    }
}

fn compare(name: &'static str, help: &'static str, f: fn(f32, f32) -> bool) -> NodeDef {
    NodeDef::new(name, CATEGORY, help)
        .input("Input 1", 0.0f32)
        .input("Input 2", 0.0f32)
        .output::<bool>("Output")
        .per_slice2(move |a: &f32, b: &f32| f(*a, *b))
}

fn boolean(name: &'static str, help: &'static str, f: fn(bool, bool) -> bool) -> NodeDef {
    NodeDef::new(name, CATEGORY, help)
        .input("Input 1", false)
        .input("Input 2", false)
        .output::<bool>("Output")
        .per_slice2(move |a: &bool, b: &bool| f(*a, *b))
}

fn spectral(name: &'static str, help: &'static str, f: fn(&[bool]) -> bool) -> NodeDef {
    NodeDef::new(name, CATEGORY, help).with_pins(|p| {
        let input = p.input_spread("Input", vec![false]);
        let output = p.output::<bool>("Output");
        move |cx| {
            let out = f(cx.get(input)?);
            cx.put(output, vec![out]);
            Ok(())
        }
    })
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::Spread;

    use crate::testing::{eval_out, floats};

    #[test]
    fn comparisons_spread() {
        let v = [
            ("Input 1", floats(&[1.0, 2.0, 3.0])),
            ("Input 2", floats(&[2.0])),
        ];
        let lt: Vec<bool> = eval_out("< (Value)", &v, "Output");
        assert_eq!(lt, [true, false, false]);
        let ge: Vec<bool> = eval_out(">= (Value)", &v, "Output");
        assert_eq!(ge, [false, true, true]);
        let eq: Vec<bool> = eval_out(
            "= (Value)",
            &[v[0].clone(), v[1].clone(), ("Epsilon", floats(&[1.0]))],
            "Output",
        );
        assert_eq!(eq, [true, true, true]);
        let ne: Vec<bool> = eval_out("!= (Value)", &v, "Output");
        assert_eq!(ne, [true, false, true]);
        let s: Vec<bool> = eval_out(
            "= (String)",
            &[
                ("Input 1", Spread::String(vec!["Abc".into()])),
                ("Input 2", Spread::String(vec!["abc".into()])),
                ("Case Sensitive", vec![true, false].into()),
            ],
            "Output",
        );
        assert_eq!(s, [false, true]);
    }

    #[test]
    fn boolean_logic() {
        let v = [
            ("Input 1", Spread::Bool(vec![false, false, true, true])),
            ("Input 2", Spread::Bool(vec![false, true, false, true])),
        ];
        let and: Vec<bool> = eval_out("AND (Boolean)", &v, "Output");
        assert_eq!(and, [false, false, false, true]);
        let or: Vec<bool> = eval_out("OR (Boolean)", &v, "Output");
        assert_eq!(or, [false, true, true, true]);
        let xor: Vec<bool> = eval_out("XOR (Boolean)", &v, "Output");
        assert_eq!(xor, [false, true, true, false]);
        let not: Vec<bool> = eval_out("NOT (Boolean)", &[("Input", v[0].1.clone())], "Output");
        assert_eq!(not, [true, true, false, false]);
        let all: Vec<bool> = eval_out(
            "AND (Boolean Spectral)",
            &[("Input", vec![true, false].into())],
            "Output",
        );
        assert_eq!(all, [false]);
        let any: Vec<bool> = eval_out(
            "OR (Boolean Spectral)",
            &[("Input", vec![true, false].into())],
            "Output",
        );
        assert_eq!(any, [true]);
    }
}
