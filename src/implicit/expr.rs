//! The formula language: parse text into an expression tree, print it back.
//!
//! Grammar (precedence low to high; `^` binds tighter than unary minus, so `-x^2 = -(x^2)`):
//! ```text
//! expr  := term (('+' | '-') term)*
//! term  := unary (('*' | '/') unary)*
//! unary := ('-' | '+') unary | power
//! power := atom ('^' integer)?          integer: [+-]?digits, or '(' [+-]?digits ')'
//! atom  := number | 'x' | 'y' | 'z' | 'pi' | func '(' expr (',' expr)* ')' | '(' expr ')'
//! func  := sqrt abs min max | sin cos exp ln (feature `mpfr`)
//! ```
use super::number::Const;
use crate::error::{Error, Result};
use std::fmt;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Min,
    Max,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnOp {
    Neg,
    Sqrt,
    Abs,
    Sin,
    Cos,
    Exp,
    Ln,
}

impl UnOp {
    /// The function's name as the parser reads it (`-` for negation).
    pub fn name(&self) -> &'static str {
        match self {
            UnOp::Neg => "-",
            UnOp::Sqrt => "sqrt",
            UnOp::Abs => "abs",
            UnOp::Sin => "sin",
            UnOp::Cos => "cos",
            UnOp::Exp => "exp",
            UnOp::Ln => "ln",
        }
    }
}

/// An expression tree. Constants keep their source text (for printing) and a
/// rigorous enclosure of the decimal value.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    Var(usize),
    Const(Const, String),
    Un(UnOp, Box<Expr>),
    Bin(BinOp, Box<Expr>, Box<Expr>),
    Pow(Box<Expr>, i32),
}

const VARS: [&str; 3] = ["x", "y", "z"];

/// Does this build have rigorous transcendental functions?
pub const HAS_MPFR: bool = cfg!(feature = "mpfr");

/// Parse a formula in the variables x, y (and z when `dim == 3`).
pub fn parse(text: &str, dim: usize) -> Result<Expr> {
    let mut p = Parser {
        chars: text.chars().collect(),
        pos: 0,
        dim,
        nesting: 0,
    };
    p.skip_ws();
    if p.pos >= p.chars.len() {
        return Err(Error::Parse {
            message: "empty formula".into(),
            column: 1,
        });
    }
    let (e, _) = p.expr()?;
    p.skip_ws();
    if p.pos < p.chars.len() {
        return Err(p.unexpected());
    }
    Ok(e)
}

/// The deepest expression tree a formula may have (nested parentheses, function calls
/// and powers count). Every pass over the tree (compilation, printing, dropping)
/// recurses, so an unbounded depth would overflow the stack; 10,000 nested parentheses
/// are rejected with this limit instead of crashing. Long chains `a + b + c + ...` and
/// `a * b / c ...` (a large polynomial read with `--formula @file`) do not count against
/// it: a chain of more than [`BALANCE_CHAIN`] operands is built as a balanced tree
/// (Σ positive terms − Σ negative terms, Π numerators / Π denominators), whose depth is
/// logarithmic; shorter chains keep the left-to-right tree of the text.
pub const MAX_DEPTH: u32 = 256;

/// Chains longer than this are built balanced (see [`MAX_DEPTH`]).
pub const BALANCE_CHAIN: usize = 32;

/// An expression with the depth of its tree.
type Node = (Expr, u32);

/// A balanced tree of `op` over `terms` (non-empty), with its depth.
fn balanced(op: BinOp, mut terms: Vec<Node>) -> Node {
    while terms.len() > 1 {
        let mut next = Vec::with_capacity(terms.len().div_ceil(2));
        let mut it = terms.into_iter();
        while let Some((a, da)) = it.next() {
            match it.next() {
                Some((b, db)) => {
                    next.push((Expr::Bin(op, Box::new(a), Box::new(b)), da.max(db) + 1))
                }
                None => next.push((a, da)),
            }
        }
        terms = next;
    }
    terms.pop().expect("non-empty")
}

/// A chain `t0 op1 t1 op2 t2 ...` where `pos`/`neg` are the two operators (Add/Sub or
/// Mul/Div): left to right when short, balanced when long.
fn chain(first: Node, rest: Vec<(BinOp, Node)>, pos: BinOp, neg: BinOp) -> Node {
    if rest.len() < BALANCE_CHAIN {
        let (mut e, mut d) = first;
        for (op, (r, dr)) in rest {
            d = d.max(dr) + 1;
            e = Expr::Bin(op, Box::new(e), Box::new(r));
        }
        return (e, d);
    }
    let mut p = vec![first];
    let mut n = Vec::new();
    for (op, t) in rest {
        if op == pos {
            p.push(t)
        } else {
            n.push(t)
        }
    }
    let (a, da) = balanced(pos, p);
    if n.is_empty() {
        return (a, da);
    }
    let (b, db) = balanced(pos, n);
    (Expr::Bin(neg, Box::new(a), Box::new(b)), da.max(db) + 1)
}

struct Parser {
    chars: Vec<char>,
    pos: usize,
    dim: usize,
    /// Current depth of the recursive descent (bounded by [`MAX_DEPTH`]).
    nesting: u32,
}

impl Parser {
    fn skip_ws(&mut self) {
        while self.pos < self.chars.len() && self.chars[self.pos].is_whitespace() {
            self.pos += 1;
        }
    }
    fn peek(&mut self) -> Option<char> {
        self.skip_ws();
        self.chars.get(self.pos).copied()
    }
    fn err(&self, message: impl Into<String>, pos: usize) -> Error {
        Error::Parse {
            message: message.into(),
            column: pos + 1,
        }
    }
    fn unexpected(&self) -> Error {
        match self.chars.get(self.pos) {
            Some(c) => self.err(format!("unexpected '{c}'"), self.pos),
            None => self.err("unexpected end of formula", self.pos),
        }
    }
    fn expect(&mut self, c: char) -> Result<()> {
        if self.peek() == Some(c) {
            self.pos += 1;
            Ok(())
        } else {
            match self.chars.get(self.pos) {
                Some(d) => Err(self.err(format!("expected '{c}' but found '{d}'"), self.pos)),
                None => Err(self.err(format!("expected '{c}' but the formula ended"), self.pos)),
            }
        }
    }
    /// A node one level above children of depth `d`, or the depth-limit error at the
    /// current position. Checked before the recursive descent goes deeper too (see
    /// [`Parser::enter`]), so neither the parser nor any later pass can overflow.
    fn up(&self, d: u32) -> Result<u32> {
        if d + 1 > MAX_DEPTH {
            return Err(self.err(
                format!("formula nested too deeply (expression depth above {MAX_DEPTH})"),
                self.pos.min(self.chars.len().saturating_sub(1)),
            ));
        }
        Ok(d + 1)
    }
    /// Count one level of recursive descent (parentheses, unary signs, arguments).
    fn enter(&mut self) -> Result<()> {
        self.nesting += 1;
        if self.nesting > MAX_DEPTH {
            return Err(self.err(
                format!("formula nested too deeply (more than {MAX_DEPTH} levels)"),
                self.pos,
            ));
        }
        Ok(())
    }
    fn expr(&mut self) -> Result<Node> {
        self.enter()?;
        let first = self.term()?;
        let mut rest = Vec::new();
        loop {
            let op = match self.peek() {
                Some('+') => BinOp::Add,
                Some('-') => BinOp::Sub,
                _ => break,
            };
            self.pos += 1;
            rest.push((op, self.term()?));
        }
        self.nesting -= 1;
        let (e, d) = chain(first, rest, BinOp::Add, BinOp::Sub);
        self.up(d.saturating_sub(1))?;
        Ok((e, d))
    }
    fn term(&mut self) -> Result<Node> {
        let first = self.unary()?;
        let mut rest = Vec::new();
        loop {
            let op = match self.peek() {
                Some('*') => BinOp::Mul,
                Some('/') => BinOp::Div,
                _ => break,
            };
            self.pos += 1;
            rest.push((op, self.unary()?));
        }
        let (e, d) = chain(first, rest, BinOp::Mul, BinOp::Div);
        self.up(d.saturating_sub(1))?;
        Ok((e, d))
    }
    fn unary(&mut self) -> Result<Node> {
        match self.peek() {
            Some('-') => {
                self.pos += 1;
                self.enter()?;
                let (a, d) = self.unary()?;
                self.nesting -= 1;
                let d = self.up(d)?;
                Ok((Expr::Un(UnOp::Neg, Box::new(a)), d))
            }
            Some('+') => {
                self.pos += 1;
                self.enter()?;
                let r = self.unary();
                self.nesting -= 1;
                r
            }
            _ => self.power(),
        }
    }
    fn power(&mut self) -> Result<Node> {
        let (base, d) = self.atom()?;
        if self.peek() != Some('^') {
            return Ok((base, d));
        }
        self.pos += 1;
        let n = self.exponent()?;
        if self.peek() == Some('^') {
            return Err(self.err("chained '^' is ambiguous; use parentheses", self.pos));
        }
        let d = self.up(d)?;
        Ok((Expr::Pow(Box::new(base), n), d))
    }
    fn exponent(&mut self) -> Result<i32> {
        let paren = self.peek() == Some('(');
        if paren {
            self.pos += 1;
        }
        let mut neg = false;
        match self.peek() {
            Some('-') => {
                neg = true;
                self.pos += 1
            }
            Some('+') => self.pos += 1,
            _ => {}
        }
        self.skip_ws();
        let start = self.pos;
        while self.pos < self.chars.len() && self.chars[self.pos].is_ascii_digit() {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(match self.chars.get(self.pos) {
                Some(c) => self.err(
                    format!("exponent must be an integer, found '{c}'"),
                    self.pos,
                ),
                None => self.err("exponent missing at end of formula", self.pos),
            });
        }
        if self.pos < self.chars.len()
            && (self.chars[self.pos] == '.' || self.chars[self.pos].is_alphabetic())
        {
            return Err(self.err("exponent must be an integer", self.pos));
        }
        let s: String = self.chars[start..self.pos].iter().collect();
        let n: i32 = s
            .parse()
            .ok()
            .filter(|n: &i32| *n <= 1000)
            .ok_or_else(|| self.err("exponent too large (at most 1000)", start))?;
        if paren {
            self.expect(')')?;
        }
        Ok(if neg { -n } else { n })
    }
    fn atom(&mut self) -> Result<Node> {
        let c = match self.peek() {
            Some(c) => c,
            None => return Err(self.err("unexpected end of formula", self.pos)),
        };
        if c == '(' {
            self.pos += 1;
            let e = self.expr()?;
            self.expect(')')?;
            return Ok(e);
        }
        if c.is_ascii_digit() || c == '.' {
            return Ok((self.number()?, 0));
        }
        if c.is_alphabetic() || c == '_' {
            let start = self.pos;
            while self.pos < self.chars.len()
                && (self.chars[self.pos].is_alphanumeric() || self.chars[self.pos] == '_')
            {
                self.pos += 1;
            }
            let name: String = self.chars[start..self.pos].iter().collect();
            if let Some(k) = VARS.iter().position(|v| *v == name) {
                if k >= self.dim {
                    return Err(self.err(
                        format!("'{name}' is not a variable of a curve f(x, y)"),
                        start,
                    ));
                }
                return Ok((Expr::Var(k), 0));
            }
            if name == "pi" {
                return Ok((Expr::Const(Const::pi(), "pi".into()), 0));
            }
            let un = match name.as_str() {
                "sqrt" => Some(UnOp::Sqrt),
                "abs" => Some(UnOp::Abs),
                "sin" => Some(UnOp::Sin),
                "cos" => Some(UnOp::Cos),
                "exp" => Some(UnOp::Exp),
                "ln" | "log" => Some(UnOp::Ln),
                _ => None,
            };
            let bin = match name.as_str() {
                "min" => Some(BinOp::Min),
                "max" => Some(BinOp::Max),
                _ => None,
            };
            if un.is_none() && bin.is_none() {
                return Err(self.err(
                    format!("unknown name '{name}' (variables: x y z; constant: pi; functions: sqrt abs min max sin cos exp ln)"),
                    start,
                ));
            }
            if matches!(un, Some(UnOp::Sin | UnOp::Cos | UnOp::Exp | UnOp::Ln)) && !HAS_MPFR {
                return Err(Error::NeedsFeature {
                    function: name,
                    column: start + 1,
                });
            }
            if self.peek() != Some('(') {
                return Err(self.err(format!("function '{name}' needs '(' after it"), self.pos));
            }
            self.pos += 1;
            let (a, da) = self.expr()?;
            if let Some(op) = bin {
                self.expect(',')?;
                let (b, db) = self.expr()?;
                self.expect(')')?;
                let d = self.up(da.max(db))?;
                return Ok((Expr::Bin(op, Box::new(a), Box::new(b)), d));
            }
            if self.peek() == Some(',') {
                return Err(self.err(format!("'{name}' takes one argument"), self.pos));
            }
            self.expect(')')?;
            let d = self.up(da)?;
            return Ok((Expr::Un(un.unwrap(), Box::new(a)), d));
        }
        Err(self.unexpected())
    }
    fn number(&mut self) -> Result<Expr> {
        let start = self.pos;
        let digits = |p: &mut Parser| {
            while p.pos < p.chars.len() && p.chars[p.pos].is_ascii_digit() {
                p.pos += 1;
            }
        };
        digits(self);
        if self.pos < self.chars.len() && self.chars[self.pos] == '.' {
            self.pos += 1;
            digits(self);
        }
        if self.pos < self.chars.len()
            && (self.chars[self.pos] == 'e' || self.chars[self.pos] == 'E')
        {
            let save = self.pos;
            self.pos += 1;
            if self.pos < self.chars.len()
                && (self.chars[self.pos] == '+' || self.chars[self.pos] == '-')
            {
                self.pos += 1;
            }
            let d0 = self.pos;
            digits(self);
            if d0 == self.pos {
                self.pos = save; // not an exponent: leave 'e' to be reported
            }
        }
        let text: String = self.chars[start..self.pos].iter().collect();
        let v: f64 = text
            .parse()
            .map_err(|_| self.err(format!("malformed number '{text}'"), start))?;
        if !v.is_finite() {
            return Err(self.err(format!("number '{text}' is out of range"), start));
        }
        if let Some(&c) = self.chars.get(self.pos) {
            if c.is_alphabetic() || c == '(' {
                return Err(self.err(
                    format!("unexpected '{c}' (write '*' for multiplication)"),
                    self.pos,
                ));
            }
        }
        Ok(Expr::Const(Const::decimal(&text, v), text))
    }
}

impl Expr {
    fn prec(&self) -> u8 {
        match self {
            Expr::Bin(BinOp::Add | BinOp::Sub, ..) => 1,
            Expr::Bin(BinOp::Mul | BinOp::Div, ..) => 2,
            Expr::Un(UnOp::Neg, _) => 3,
            Expr::Pow(..) => 4,
            _ => 5,
        }
    }
    /// Does the expression use the variable `k`?
    pub fn uses_var(&self, k: usize) -> bool {
        match self {
            Expr::Var(j) => *j == k,
            Expr::Const(..) => false,
            Expr::Un(_, a) | Expr::Pow(a, _) => a.uses_var(k),
            Expr::Bin(_, a, b) => a.uses_var(k) || b.uses_var(k),
        }
    }
}

impl fmt::Display for Expr {
    /// Prints with the fewest parentheses that reparse to the same tree.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let wrap = |f: &mut fmt::Formatter<'_>, e: &Expr, paren: bool| -> fmt::Result {
            if paren {
                write!(f, "({e})")
            } else {
                write!(f, "{e}")
            }
        };
        match self {
            Expr::Var(k) => write!(f, "{}", VARS[*k]),
            Expr::Const(_, t) => write!(f, "{t}"),
            Expr::Un(UnOp::Neg, a) => {
                write!(f, "-")?;
                // -(-x) and -(a+b) need parentheses; a power binds tighter than minus.
                wrap(f, a, a.prec() < 4)
            }
            Expr::Un(op, a) => {
                write!(f, "{}({a})", op.name())
            }
            Expr::Pow(a, n) => {
                wrap(f, a, a.prec() < 5)?;
                if *n < 0 {
                    write!(f, "^({n})")
                } else {
                    write!(f, "^{n}")
                }
            }
            Expr::Bin(op @ (BinOp::Min | BinOp::Max), a, b) => {
                write!(
                    f,
                    "{}({a}, {b})",
                    if *op == BinOp::Min { "min" } else { "max" }
                )
            }
            Expr::Bin(op, a, b) => {
                let p = self.prec();
                let sym = match op {
                    BinOp::Add => " + ",
                    BinOp::Sub => " - ",
                    BinOp::Mul => " * ",
                    BinOp::Div => " / ",
                    _ => unreachable!(),
                };
                // Left-associative: the left operand needs parentheses only at lower
                // precedence, the right one also at equal precedence.
                wrap(f, a, a.prec() < p)?;
                write!(f, "{sym}")?;
                wrap(f, b, b.prec() <= p)
            }
        }
    }
}
