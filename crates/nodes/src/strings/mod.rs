//! Strings: `Format` (templates with numbered inputs), `Split`,
//! `Concatenate` (per slice and over a spread), conversions to and from text
//! (`AsString` for values, integers, toggles, vectors and colours, `AsValue`,
//! `AsColor`) and the everyday edits (`Length`, `Replace`, `Substring`,
//! `UpperCase`, `LowerCase`, `Trim`, `Pos`). Lengths and positions count
//! characters (Unicode scalar values), not bytes.

mod convert;
mod format;

use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry};

use crate::spreads::MAX_SLICES;
use crate::typed::Value;

const CATEGORY: &str = "String";
const FORMAT_INPUTS: [&str; 3] = ["Input 0", "Input 1", "Input 2"];

pub fn register(r: &mut Registry) {
    convert::register(r);
    r.add(format_node::<String>(
        "Format (String)",
        "Fills Format with the inputs: `{0}`, `{1}`, `{2}` stand for Input 0 to 2, `{}` for the \
         next one, `{{` and `}}` for braces. Every pin spreads: one text per slice.",
        String::new(),
        |s, _| s.clone(),
    ));
    r.add(format_node::<f32>(
        "Format (Value)",
        "Fills Format with the values: `{0}`, `{1}`, `{2}` stand for Input 0 to 2 (shortest \
         form), `{0:.2}` with two decimals, `{}` for the next one, `{{` and `}}` for braces. \
         Every pin spreads: one text per slice.",
        0.0,
        |v, decimals| match decimals {
            Some(d) => format!("{v:.d$}"),
            None => format!("{v}"),
        },
    ));
    r.add(
        NodeDef::new(
            "Split (String)",
            CATEGORY,
            "Cuts each slice of Input at every Separator (an empty Separator cuts between \
             characters). Keep Empty keeps the empty pieces between two separators. Former Slice \
             gives, for each piece, the Input slice it came from.",
        )
        .with_pins(|p| {
            let input = p.input("Input", String::new());
            let separator = p.input("Separator", " ".to_owned());
            let keep_empty = p.input("Keep Empty", false);
            let output = p.output::<String>("Output");
            let former_slice = p.output::<i64>("Former Slice");
            move |cx| {
                let (pieces, former) = split(cx, input, separator, keep_empty)?;
                cx.put(output, pieces);
                cx.put(former_slice, former);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Concatenate (String)",
            CATEGORY,
            "Input 1, Intersperse and Input 2 one after the other, slice by slice.",
        )
        .input("Input 1", String::new())
        .input("Input 2", String::new())
        .input("Intersperse", String::new())
        .output::<String>("Output")
        .per_slice3(|a: &String, b: &String, sep: &String| format!("{a}{sep}{b}")),
    );
    r.add(
        NodeDef::new(
            "Concatenate (String Spectral)",
            CATEGORY,
            "Joins the slices of each bin of Input into one text, Intersperse between them \
             (Bin Size -1, the default: the whole spread into one text).",
        )
        .with_pins(|p| {
            let input = p.input("Input", String::new());
            let intersperse = p.input("Intersperse", String::new());
            let bin_size = p.input("Bin Size", -1i64);
            let output = p.output::<String>("Output");
            move |cx| {
                let input = cx.get(input)?;
                let sep = cx.get(intersperse)?.first().cloned().unwrap_or_default();
                let bins = crate::spreads::bins::bins_of(cx, input.len(), bin_size)?;
                let out: Vec<String> = bins.into_iter().map(|b| input[b].join(&sep)).collect();
                cx.put(output, out);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Length (String)",
            CATEGORY,
            "The number of characters of each slice.",
        )
        .input("Input", String::new())
        .output::<i64>("Count")
        .per_slice1(|s: &String| s.chars().count() as i64),
    );
    r.add(
        NodeDef::new(
            "Replace (String)",
            CATEGORY,
            "Input with every Find replaced by Replace With, slice by slice (an empty Find \
             changes nothing).",
        )
        .input("Input", String::new())
        .input("Find", String::new())
        .input("Replace With", String::new())
        .output::<String>("Output")
        .per_slice3(|s: &String, find: &String, with: &String| {
            if find.is_empty() {
                s.clone()
            } else {
                s.replace(find.as_str(), with)
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Substring (String)",
            CATEGORY,
            "Count characters of Input from character Start (0 is the first; a negative Start \
             counts from the end), slice by slice. What lies beyond the text is left out.",
        )
        .input("Input", String::new())
        .input("Start", 0i64)
        .input("Count", 1i64)
        .output::<String>("Output")
        .per_slice3(|s: &String, start: &i64, count: &i64| substring(s, *start, *count)),
    );
    r.add(
        NodeDef::new(
            "UpperCase (String)",
            CATEGORY,
            "Input in capitals, slice by slice.",
        )
        .input("Input", String::new())
        .output::<String>("Output")
        .per_slice1(|s: &String| s.to_uppercase()),
    );
    r.add(
        NodeDef::new(
            "LowerCase (String)",
            CATEGORY,
            "Input in small letters, slice by slice.",
        )
        .input("Input", String::new())
        .output::<String>("Output")
        .per_slice1(|s: &String| s.to_lowercase()),
    );
    r.add(
        NodeDef::new(
            "Trim (String)",
            CATEGORY,
            "Input without white space at its start and end, slice by slice.",
        )
        .input("Input", String::new())
        .output::<String>("Output")
        .per_slice1(|s: &String| s.trim().to_owned()),
    );
    r.add(
        NodeDef::new(
            "Pos (String)",
            CATEGORY,
            "The character position of the first Find in Input, or -1 when it does not occur, \
             slice by slice.",
        )
        .input("Input", String::new())
        .input("Find", String::new())
        .output::<i64>("Position")
        .per_slice2(|s: &String, find: &String| match s.find(find.as_str()) {
            Some(byte) => s[..byte].chars().count() as i64,
            None => -1,
        }),
    );
}

fn format_node<T: Value>(
    name: &'static str,
    help: &'static str,
    default: T,
    show: fn(&T, Option<usize>) -> String,
) -> NodeDef {
    NodeDef::new(name, CATEGORY, help).with_pins_node(|p| {
        let template = p.input("Format", "{0}".to_owned());
        let inputs = FORMAT_INPUTS.map(|pin| p.input(pin, default.clone()));
        let output = p.output::<String>("Output");
        move || FormatNode::<T> {
            template,
            inputs,
            output,
            show,
            cache: None,
        }
    })
}

struct FormatNode<T: Value> {
    template: In<String>,
    /// Input 0 to 2, the `{0}` to `{2}` of the template.
    inputs: [In<T>; FORMAT_INPUTS.len()],
    output: Out<String>,
    show: fn(&T, Option<usize>) -> String,
    /// The last template and its parse, so an unchanged template is not parsed again.
    cache: Option<(String, Vec<format::Piece>)>,
}

impl<T: Value> Node for FormatNode<T> {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let templates = cx.get(self.template)?;
        let inputs = self
            .inputs
            .iter()
            .map(|&pin| cx.get(pin))
            .collect::<Result<Vec<_>, _>>()?;
        let n = slice_count(
            [templates.len()]
                .into_iter()
                .chain(inputs.iter().map(|s| s.len())),
        );
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            let template = wrapped(templates, i);
            if self.cache.as_ref().is_none_or(|(t, _)| t != template) {
                let pieces = format::parse(template, FORMAT_INPUTS.len())
                    .map_err(|e| cx.error(self.template, e))?;
                self.cache = Some((template.clone(), pieces));
            }
            let (_, pieces) = self.cache.as_ref().expect("just parsed");
            out.push(format::render(pieces, |k, d| {
                (self.show)(wrapped(inputs[k], i), d)
            }));
        }
        cx.put(self.output, out);
        Ok(())
    }
}

/// Split's pieces and, for each, the Input slice it came from.
fn split(
    cx: &EvalContext<'_>,
    input_pin: In<String>,
    separator: In<String>,
    keep_empty: In<bool>,
) -> Result<(Vec<String>, Vec<i64>), NodeError> {
    let (input, sep, keep) = (cx.get(input_pin)?, cx.get(separator)?, cx.get(keep_empty)?);
    let n = slice_count([input.len(), sep.len(), keep.len()]);
    let (mut out, mut former) = (Vec::new(), Vec::new());
    for i in 0..n {
        let (s, sep, keep) = (wrapped(input, i), wrapped(sep, i), *wrapped(keep, i));
        let pieces: Vec<String> = if sep.is_empty() {
            s.chars().map(String::from).collect()
        } else {
            s.split(sep.as_str()).map(str::to_owned).collect()
        };
        for p in pieces.into_iter().filter(|p| keep || !p.is_empty()) {
            out.push(p);
            former.push(i as i64);
        }
        if out.len() > MAX_SLICES {
            return Err(cx.error(input_pin, format!("more than {MAX_SLICES} pieces")));
        }
    }
    Ok((out, former))
}

fn substring(s: &str, start: i64, count: i64) -> String {
    let len = s.chars().count() as i64;
    let start = if start < 0 {
        (len + start).max(0)
    } else {
        start
    };
    let take = usize::try_from(count.max(0)).unwrap_or(usize::MAX);
    s.chars()
        .skip(usize::try_from(start).unwrap_or(usize::MAX))
        .take(take)
        .collect()
}

#[cfg(test)]
mod tests {
    use crate::testing::{eval, eval_err, eval_out, floats, ints, strings_of as strings};

    #[test]
    fn format_fills_templates_per_slice() {
        let out: Vec<String> = eval_out(
            "Format (Value)",
            &[
                ("Format", strings(&["x={0:.1} y={1}", "{} and {}"])),
                ("Input 0", floats(&[1.25])),
                ("Input 1", floats(&[2.0])),
            ],
            "Output",
        );
        assert_eq!(out, ["x=1.2 y=2", "1.25 and 2"]);
        let out: Vec<String> = eval_out(
            "Format (String)",
            &[
                ("Format", strings(&["<{2}{0}>"])),
                ("Input 0", strings(&["a", "b"])),
                ("Input 2", strings(&["-"])),
            ],
            "Output",
        );
        assert_eq!(out, ["<-a>", "<-b>"]);
        eval_err(
            "Format (String)",
            &[("Format", strings(&["{7}"]))],
            "Format",
        );
    }

    #[test]
    fn split_and_concatenate() {
        let out = eval(
            "Split (String)",
            &[
                ("Input", strings(&["a,b,,c", "d"])),
                ("Separator", strings(&[","])),
            ],
        )
        .expect("split");
        assert_eq!(out[0], strings(&["a", "b", "c", "d"]));
        assert_eq!(out[1], ints(&[0, 0, 0, 1]));
        let kept: Vec<String> = eval_out(
            "Split (String)",
            &[
                ("Input", strings(&["a,,b"])),
                ("Separator", strings(&[","])),
                ("Keep Empty", vec![true].into()),
            ],
            "Output",
        );
        assert_eq!(kept, ["a", "", "b"]);
        let chars: Vec<String> = eval_out(
            "Split (String)",
            &[("Input", strings(&["hé!"])), ("Separator", strings(&[""]))],
            "Output",
        );
        assert_eq!(chars, ["h", "é", "!"]);
        let cat: Vec<String> = eval_out(
            "Concatenate (String)",
            &[
                ("Input 1", strings(&["a", "b"])),
                ("Input 2", strings(&["x"])),
                ("Intersperse", strings(&["-"])),
            ],
            "Output",
        );
        assert_eq!(cat, ["a-x", "b-x"]);
        let joined: Vec<String> = eval_out(
            "Concatenate (String Spectral)",
            &[
                ("Input", strings(&["a", "b", "c"])),
                ("Intersperse", strings(&[", "])),
            ],
            "Output",
        );
        assert_eq!(joined, ["a, b, c"]);
    }

    #[test]
    fn everyday_edits_count_characters() {
        let s = ("Input", strings(&["  Héllo wörld  "]));
        let len: Vec<i64> = eval_out("Length (String)", std::slice::from_ref(&s), "Count");
        assert_eq!(len, [15]);
        let t: Vec<String> = eval_out("Trim (String)", std::slice::from_ref(&s), "Output");
        assert_eq!(t, ["Héllo wörld"]);
        let u: Vec<String> = eval_out("UpperCase (String)", std::slice::from_ref(&s), "Output");
        assert_eq!(u, ["  HÉLLO WÖRLD  "]);
        let pos: Vec<i64> = eval_out(
            "Pos (String)",
            &[s.clone(), ("Find", strings(&["w", "z"]))],
            "Position",
        );
        assert_eq!(pos, [8, -1]);
        let sub: Vec<String> = eval_out(
            "Substring (String)",
            &[
                ("Input", strings(&["Héllo"])),
                ("Start", ints(&[1, -2, 9])),
                ("Count", ints(&[3])),
            ],
            "Output",
        );
        assert_eq!(sub, ["éll", "lo", ""]);
        let rep: Vec<String> = eval_out(
            "Replace (String)",
            &[
                ("Input", strings(&["a.b.c"])),
                ("Find", strings(&["."])),
                ("Replace With", strings(&["::"])),
            ],
            "Output",
        );
        assert_eq!(rep, ["a::b::c"]);
    }
}
