//! Comment-aware text helpers shared by the fallback analysis and the rewrite.
//!
//! Everything works on a copy of the source with comments blanked to spaces, byte for byte and
//! newline for newline, so offsets and line numbers found in the copy are valid in the original:
//! the rewrite can then splice into the app's own text without ever re-printing it.

/// Per byte: is it part of a comment (delimiters included)? A line comment's ending newline is
/// not; a newline inside a block comment is.
pub fn comment_mask(src: &str) -> Vec<bool> {
    let bytes = src.as_bytes();
    let mut mask = vec![false; bytes.len()];
    let mut i = 0;
    while i < bytes.len() {
        let end = match (bytes[i], bytes.get(i + 1)) {
            (b'/', Some(b'/')) => src[i..].find('\n').map_or(bytes.len(), |e| i + e),
            (b'/', Some(b'*')) => src[i + 2..].find("*/").map_or(bytes.len(), |e| i + 2 + e + 2),
            _ => {
                i += 1;
                continue;
            }
        };
        mask[i..end].iter_mut().for_each(|m| *m = true);
        i = end;
    }
    mask
}

/// Does the source end inside a `/* ...` comment that is never closed?
pub fn ends_in_block_comment(src: &str) -> bool {
    let bytes = src.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match (bytes[i], bytes.get(i + 1)) {
            (b'/', Some(b'/')) => i = src[i..].find('\n').map_or(bytes.len(), |e| i + e),
            (b'/', Some(b'*')) => match src[i + 2..].find("*/") {
                Some(e) => i += 2 + e + 2,
                None => return true,
            },
            _ => i += 1,
        }
    }
    false
}

/// The source with every comment byte replaced by a space, newlines kept.
pub fn blank_comments(src: &str) -> String {
    let mask = comment_mask(src);
    let out: Vec<u8> = src
        .bytes()
        .zip(mask)
        .map(|(b, in_comment)| if in_comment && b != b'\n' { b' ' } else { b })
        .collect();
    // Comments end on ASCII delimiters, so whole characters were replaced: still valid UTF-8.
    String::from_utf8_lossy(&out).into_owned()
}

/// A preprocessor directive found on one (comment-blanked) line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Directive {
    /// 0-based line index.
    pub line: usize,
    pub name: String,
    pub rest: String,
}

/// All directives of a comment-blanked source, in order.
pub fn directives(blanked: &str) -> Vec<Directive> {
    let mut out = Vec::new();
    for (line, text) in blanked.lines().enumerate() {
        let Some(body) = text.trim_start().strip_prefix('#') else {
            continue;
        };
        let body = body.trim_start();
        let split = body.find(|c: char| !c.is_ascii_alphanumeric() && c != '_');
        let (name, rest) = body.split_at(split.unwrap_or(body.len()));
        out.push(Directive {
            line,
            name: name.to_string(),
            rest: rest.trim().to_string(),
        });
    }
    out
}

/// `(#version number, is_es)` and the directive's line, from the first directive if it is `#version`.
pub fn version(dirs: &[Directive]) -> Option<((u32, bool), usize)> {
    let first = dirs.first().filter(|d| d.name == "version")?;
    let mut words = first.rest.split_whitespace();
    let number: u32 = words.next()?.parse().ok()?;
    let es = number == 100 || words.next() == Some("es");
    Some(((number, es), first.line))
}

/// The line after which code may be inserted so that it follows `line` and stays outside any
/// `#if` block that is open there (the app's `#extension` lines may sit inside `#ifdef`s).
pub fn line_after_conditionals(dirs: &[Directive], line: usize) -> usize {
    let mut depth = 0i32;
    let mut result = line;
    for d in dirs {
        match d.name.as_str() {
            "if" | "ifdef" | "ifndef" => depth += 1,
            "endif" => depth -= 1,
            _ => {}
        }
        if d.line == line && depth <= 0 {
            return line;
        }
        if d.line > line && depth <= 0 {
            result = d.line;
            break;
        }
    }
    result
}

/// Byte offset just past the newline that ends `line`, skipping forward while that newline is
/// inside a block comment (inserting there would put our code in the comment), and the number
/// of lines before that offset. `None` when the source ends first (the caller adds a newline).
pub fn offset_after_line(src: &str, line: usize) -> Option<(usize, usize)> {
    let mask = comment_mask(src);
    let mut current = 0usize;
    for (i, b) in src.bytes().enumerate() {
        if b != b'\n' {
            continue;
        }
        if current >= line && !mask[i] {
            return Some((i + 1, current + 1));
        }
        current += 1;
    }
    None
}

/// A token of the comment-blanked source: identifiers/keywords, numbers and punctuation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Token {
    Ident(String),
    Number(String),
    Punct(String),
}

impl Token {
    pub fn is_ident(&self, s: &str) -> bool {
        matches!(self, Token::Ident(i) if i == s)
    }
    pub fn is_punct(&self, s: &str) -> bool {
        matches!(self, Token::Punct(p) if p == s)
    }
}

const TWO_CHAR_PUNCT: [&str; 19] = [
    "==", "!=", "<=", ">=", "&&", "||", "^^", "++", "--", "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "<<", ">>",
];

/// Tokens of the code, preprocessor lines excluded (macros are not expanded: a text-level view).
pub fn tokens(blanked: &str) -> Vec<Token> {
    let code: String = blanked
        .lines()
        .map(|l| if l.trim_start().starts_with('#') { "" } else { l })
        .collect::<Vec<_>>()
        .join("\n");
    let chars: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let start = i;
        if c.is_whitespace() {
            i += 1;
        } else if c.is_alphabetic() || c == '_' {
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push(Token::Ident(chars[start..i].iter().collect()));
        } else if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(char::is_ascii_digit)) {
            i = scan_number(&chars, i);
            out.push(Token::Number(chars[start..i].iter().collect()));
        } else {
            let two: String = chars[i..(i + 2).min(chars.len())].iter().collect();
            let len = if TWO_CHAR_PUNCT.contains(&two.as_str()) { 2 } else { 1 };
            i += len;
            out.push(Token::Punct(chars[start..i].iter().collect()));
        }
    }
    out
}

fn scan_number(chars: &[char], mut i: usize) -> usize {
    while i < chars.len() {
        let c = chars[i];
        let exponent_sign = (c == '+' || c == '-') && matches!(chars[i - 1], 'e' | 'E');
        if c.is_ascii_alphanumeric() || c == '.' || exponent_sign {
            i += 1;
        } else {
            break;
        }
    }
    i
}

/// True when `name` occurs as a whole identifier in the (blanked) code.
pub fn has_ident(blanked: &str, name: &str) -> bool {
    tokens(blanked).iter().any(|t| t.is_ident(name))
}
