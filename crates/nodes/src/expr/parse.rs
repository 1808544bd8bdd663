//! The expression grammar: text to an untyped syntax tree, with the
//! character position of every piece so errors can point at it.
//!
//! ```text
//! expr    := compare
//! compare := sum (('<' | '>' | '<=' | '>=' | '==' | '!=') sum)?
//! sum     := product (('+' | '-') product)*
//! product := unary (('*' | '/' | '%') unary)*
//! unary   := '-' unary | power
//! power   := postfix ('^' unary)?
//! postfix := primary ('.' swizzle)*
//! primary := number | name | name '(' (expr (',' expr)*)? ')' | '(' expr ')'
//! ```

use std::fmt;

/// A parse or type error at a character position (0 = the first character).
#[derive(Clone, Debug, PartialEq)]
pub struct ExprError {
    pub at: usize,
    pub message: String,
}

impl fmt::Display for ExprError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "at character {}: {}", self.at + 1, self.message)
    }
}

pub(crate) fn error<T>(at: usize, message: impl Into<String>) -> Result<T, ExprError> {
    Err(ExprError {
        at,
        message: message.into(),
    })
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Pow,
    Lt,
    Gt,
    Le,
    Ge,
    Eq,
    Ne,
}

/// The syntax tree; each node keeps where it starts.
#[derive(Clone, Debug, PartialEq)]
pub enum Ast {
    Num(f32),
    Name(String, usize),
    Call(String, Vec<Ast>, usize),
    Binary(BinOp, Box<Ast>, Box<Ast>, usize),
    Neg(Box<Ast>),
    Swizzle(Box<Ast>, String, usize),
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(f32),
    Name(String),
    Sym(&'static str),
    End,
}

fn lex(text: &str) -> Result<Vec<(Tok, usize)>, ExprError> {
    let chars: Vec<char> = text.chars().collect();
    let mut toks = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let start = i;
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        let next_is_digit = chars.get(i + 1).is_some_and(char::is_ascii_digit);
        if c.is_ascii_digit() || (c == '.' && next_is_digit && !after_value(&toks)) {
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let s: String = chars[start..i].iter().collect();
            let v: f32 = s
                .parse()
                .or_else(|_| error(start, format!("`{s}` is not a number")))?;
            toks.push((Tok::Num(v), start));
        } else if c.is_alphabetic() || c == '_' {
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            toks.push((Tok::Name(chars[start..i].iter().collect()), start));
        } else {
            let two: String = chars[i..(i + 2).min(chars.len())].iter().collect();
            let sym = ["<=", ">=", "==", "!="]
                .into_iter()
                .find(|s| *s == two)
                .or_else(|| {
                    ["+", "-", "*", "/", "%", "^", "(", ")", ",", ".", "<", ">"]
                        .into_iter()
                        .find(|s| s.starts_with(c))
                });
            let Some(sym) = sym else {
                return error(start, format!("unexpected `{c}`"));
            };
            i += sym.len();
            toks.push((Tok::Sym(sym), start));
        }
    }
    toks.push((Tok::End, chars.len()));
    Ok(toks)
}

/// Whether the last token ends a value (so `.` after it is a swizzle, not a number).
fn after_value(toks: &[(Tok, usize)]) -> bool {
    matches!(
        toks.last(),
        Some((Tok::Name(_) | Tok::Num(_) | Tok::Sym(")"), _))
    )
}

/// Parse an expression.
pub fn parse(text: &str) -> Result<Ast, ExprError> {
    let toks = lex(text)?;
    let mut p = Parser { toks, pos: 0 };
    let ast = p.expr()?;
    match p.peek() {
        (Tok::End, _) => Ok(ast),
        (t, at) => error(
            at,
            format!("unexpected {} after the expression", describe(&t)),
        ),
    }
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Num(v) => format!("number `{v}`"),
        Tok::Name(n) => format!("`{n}`"),
        Tok::Sym(s) => format!("`{s}`"),
        Tok::End => "end".to_owned(),
    }
}

struct Parser {
    toks: Vec<(Tok, usize)>,
    pos: usize,
}

impl Parser {
    fn peek(&self) -> (Tok, usize) {
        self.toks[self.pos].clone()
    }

    fn eat(&mut self, sym: &str) -> bool {
        if matches!(&self.toks[self.pos].0, Tok::Sym(s) if *s == sym) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn expect(&mut self, sym: &str) -> Result<(), ExprError> {
        if self.eat(sym) {
            return Ok(());
        }
        let (t, at) = self.peek();
        error(at, format!("expected `{sym}`, found {}", describe(&t)))
    }

    fn expr(&mut self) -> Result<Ast, ExprError> {
        let left = self.sum()?;
        let at = self.peek().1;
        for (sym, op) in [
            ("<=", BinOp::Le),
            (">=", BinOp::Ge),
            ("==", BinOp::Eq),
            ("!=", BinOp::Ne),
            ("<", BinOp::Lt),
            (">", BinOp::Gt),
        ] {
            if self.eat(sym) {
                let right = self.sum()?;
                return Ok(Ast::Binary(op, Box::new(left), Box::new(right), at));
            }
        }
        Ok(left)
    }

    fn sum(&mut self) -> Result<Ast, ExprError> {
        let mut left = self.product()?;
        loop {
            let at = self.peek().1;
            let op = if self.eat("+") {
                BinOp::Add
            } else if self.eat("-") {
                BinOp::Sub
            } else {
                return Ok(left);
            };
            left = Ast::Binary(op, Box::new(left), Box::new(self.product()?), at);
        }
    }

    fn product(&mut self) -> Result<Ast, ExprError> {
        let mut left = self.unary()?;
        loop {
            let at = self.peek().1;
            let op = if self.eat("*") {
                BinOp::Mul
            } else if self.eat("/") {
                BinOp::Div
            } else if self.eat("%") {
                BinOp::Rem
            } else {
                return Ok(left);
            };
            left = Ast::Binary(op, Box::new(left), Box::new(self.unary()?), at);
        }
    }

    fn unary(&mut self) -> Result<Ast, ExprError> {
        if self.eat("-") {
            return Ok(Ast::Neg(Box::new(self.unary()?)));
        }
        let base = self.postfix()?;
        let at = self.peek().1;
        if self.eat("^") {
            // Right-associative, and binds tighter than a leading minus: -2^2 = -4.
            let exponent = self.unary()?;
            return Ok(Ast::Binary(
                BinOp::Pow,
                Box::new(base),
                Box::new(exponent),
                at,
            ));
        }
        Ok(base)
    }

    fn postfix(&mut self) -> Result<Ast, ExprError> {
        let mut value = self.primary()?;
        while self.eat(".") {
            match self.peek() {
                (Tok::Name(s), at) => {
                    self.pos += 1;
                    value = Ast::Swizzle(Box::new(value), s, at);
                }
                (t, at) => {
                    return error(
                        at,
                        format!("expected a swizzle like `.xy`, found {}", describe(&t)),
                    );
                }
            }
        }
        Ok(value)
    }

    fn primary(&mut self) -> Result<Ast, ExprError> {
        let (tok, at) = self.peek();
        self.pos += 1;
        match tok {
            Tok::Num(v) => Ok(Ast::Num(v)),
            Tok::Name(name) => {
                if !self.eat("(") {
                    return Ok(Ast::Name(name, at));
                }
                let mut args = Vec::new();
                if !self.eat(")") {
                    loop {
                        args.push(self.expr()?);
                        if self.eat(")") {
                            break;
                        }
                        self.expect(",")?;
                    }
                }
                Ok(Ast::Call(name, args, at))
            }
            Tok::Sym("(") => {
                let inner = self.expr()?;
                self.expect(")")?;
                Ok(inner)
            }
            t => error(at, format!("expected a value, found {}", describe(&t))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Ast, BinOp, parse};

    #[test]
    fn precedence_and_positions() {
        let ast = parse("a + b * 2").expect("parses");
        let Ast::Binary(BinOp::Add, _, right, 2) = ast else {
            panic!("{ast:?}")
        };
        assert!(matches!(*right, Ast::Binary(BinOp::Mul, _, _, 6)));
        assert_eq!(
            parse("-2^2").expect("pow"),
            Ast::Neg(Box::new(Ast::Binary(
                BinOp::Pow,
                Box::new(Ast::Num(2.0)),
                Box::new(Ast::Num(2.0)),
                2
            )))
        );
        assert!(matches!(parse("u.xy").expect("swizzle"), Ast::Swizzle(_, s, 2) if s == "xy"));
        assert_eq!(parse(".5e1").expect("number"), Ast::Num(5.0));
        assert!(
            matches!(parse("f()").expect("call"), Ast::Call(n, a, 0) if n == "f" && a.is_empty())
        );
    }

    #[test]
    fn errors_point_at_the_problem() {
        assert_eq!(parse("a +").expect_err("end").at, 3);
        assert_eq!(parse("a $ b").expect_err("char").at, 2);
        assert_eq!(parse("(a").expect_err("paren").at, 2);
        assert_eq!(parse("a b").expect_err("two").at, 2);
        assert_eq!(parse("sin(a,").expect_err("arg").at, 6);
    }
}
