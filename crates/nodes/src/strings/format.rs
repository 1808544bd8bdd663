//! The template language of `Format (String)` and `Format (Value)`:
//! `{0}`, `{1}`, `{2}` name the inputs, `{}` takes the next one, `{0:.2}`
//! gives a value two decimals, `{{` and `}}` are literal braces.

/// One piece of a parsed template.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Piece {
    Text(String),
    /// Input index and, for values, the number of decimals.
    Arg {
        index: usize,
        decimals: Option<usize>,
    },
}

/// Parse `template` for `inputs` inputs. The error says what is wrong and at which character.
pub(crate) fn parse(template: &str, inputs: usize) -> Result<Vec<Piece>, String> {
    let mut pieces = Vec::new();
    let mut text = String::new();
    let mut next_arg = 0;
    let mut chars = template.char_indices().peekable();
    while let Some((at, c)) = chars.next() {
        match c {
            '{' if chars.peek().map(|p| p.1) == Some('{') => {
                chars.next();
                text.push('{');
            }
            '}' if chars.peek().map(|p| p.1) == Some('}') => {
                chars.next();
                text.push('}');
            }
            '}' => {
                return Err(format!(
                    "a lone `}}` at character {at} (write `}}}}` for a brace)"
                ));
            }
            '{' => {
                let mut spec = String::new();
                loop {
                    match chars.next() {
                        Some((_, '}')) => break,
                        Some((_, c)) => spec.push(c),
                        None => return Err(format!("the `{{` at character {at} is never closed")),
                    }
                }
                let (index, decimals) = match spec.split_once(':') {
                    Some((i, d)) => (i, Some(d)),
                    None => (spec.as_str(), None),
                };
                let index = if index.trim().is_empty() {
                    next_arg
                } else {
                    index.trim().parse::<usize>().map_err(|_| {
                        format!("`{{{spec}}}` at character {at}: `{index}` is not an input number")
                    })?
                };
                if index >= inputs {
                    return Err(format!(
                        "`{{{spec}}}` at character {at}: there are only inputs 0 to {}",
                        inputs - 1
                    ));
                }
                let decimals = decimals
                    .map(|d| {
                        d.strip_prefix('.')
                            .and_then(|n| n.parse::<usize>().ok())
                            .filter(|&n| n <= 16)
                            .ok_or_else(|| format!("`{{{spec}}}` at character {at}: write decimals as `:.2` (0 to 16)"))
                    })
                    .transpose()?;
                next_arg = index + 1;
                if !text.is_empty() {
                    pieces.push(Piece::Text(std::mem::take(&mut text)));
                }
                pieces.push(Piece::Arg { index, decimals });
            }
            c => text.push(c),
        }
    }
    if !text.is_empty() {
        pieces.push(Piece::Text(text));
    }
    Ok(pieces)
}

/// Fill a parsed template; `arg(index, decimals)` renders one input.
pub(crate) fn render(
    pieces: &[Piece],
    mut arg: impl FnMut(usize, Option<usize>) -> String,
) -> String {
    let mut out = String::new();
    for piece in pieces {
        match piece {
            Piece::Text(t) => out.push_str(t),
            Piece::Arg { index, decimals } => out.push_str(&arg(*index, *decimals)),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{Piece, parse, render};

    #[test]
    fn templates_parse_with_positions_and_escapes() {
        let p = parse("x={0:.2}, {} {{ok}}", 3).expect("parses");
        assert_eq!(
            p,
            [
                Piece::Text("x=".into()),
                Piece::Arg {
                    index: 0,
                    decimals: Some(2)
                },
                Piece::Text(", ".into()),
                Piece::Arg {
                    index: 1,
                    decimals: None
                },
                Piece::Text(" {ok}".into()),
            ]
        );
        let s = render(&p, |i, d| format!("<{i}{d:?}>"));
        assert_eq!(s, "x=<0Some(2)>, <1None> {ok}");
    }

    #[test]
    fn bad_templates_say_where() {
        assert!(
            parse("{3}", 3)
                .expect_err("range")
                .contains("only inputs 0 to 2")
        );
        assert!(parse("a {0", 3).expect_err("open").contains("character 2"));
        assert!(parse("}", 3).expect_err("lone").contains("lone"));
        assert!(
            parse("{x}", 3)
                .expect_err("name")
                .contains("not an input number")
        );
        assert!(parse("{0:2}", 3).expect_err("decimals").contains(":.2"));
    }
}
