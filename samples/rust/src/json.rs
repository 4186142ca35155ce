//! A small strict JSON reader (RFC 8259), enough for a performance file: the
//! grammar of the C sample's json.c, nesting bounded so that a hostile file
//! cannot exhaust the stack.

#[derive(Debug, Clone, PartialEq)]
pub enum Json {
    Null,
    Bool(bool),
    Number(f64),
    String(String),
    Array(Vec<Json>),
    /// Members in file order; a repeated name keeps every occurrence.
    Object(Vec<(String, Json)>),
}

impl Json {
    /// The member `key` of an object (the last one if repeated).
    pub fn get(&self, key: &str) -> Option<&Json> {
        match self {
            Json::Object(members) => members.iter().rev().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }
}

const MAX_DEPTH: usize = 64;

struct Parser<'a> {
    s: &'a [u8],
    p: usize,
}

/// Parses a whole document; the error is "line L, column C: problem".
pub fn parse(text: &[u8]) -> Result<Json, String> {
    let mut ps = Parser { s: text, p: 0 };
    if text.starts_with(b"\xEF\xBB\xBF") {
        ps.p = 3; // byte order mark
    }
    let v = ps.value(0)?;
    ps.skip_space();
    if ps.p != ps.s.len() {
        return Err(ps.fail("unexpected text after the JSON value"));
    }
    Ok(v)
}

impl<'a> Parser<'a> {
    fn fail(&self, what: &str) -> String {
        let upto = &self.s[..self.p.min(self.s.len())];
        let line = 1 + upto.iter().filter(|&&c| c == b'\n').count();
        let column = 1 + upto.iter().rev().take_while(|&&c| c != b'\n').count();
        format!("line {line}, column {column}: {what}")
    }

    fn peek(&self) -> Option<u8> {
        self.s.get(self.p).copied()
    }

    fn skip_space(&mut self) {
        while matches!(self.peek(), Some(b' ' | b'\t' | b'\n' | b'\r')) {
            self.p += 1;
        }
    }

    fn literal(&mut self, word: &str) -> bool {
        if self.s[self.p..].starts_with(word.as_bytes()) {
            self.p += word.len();
            return true;
        }
        false
    }

    fn value(&mut self, depth: usize) -> Result<Json, String> {
        self.skip_space();
        match self.peek() {
            None => Err(self.fail("unexpected end of input")),
            Some(b'{') | Some(b'[') => {
                let close = if self.peek() == Some(b'{') { b'}' } else { b']' };
                self.p += 1;
                self.container(depth, close)
            }
            Some(b'"') => {
                self.p += 1;
                Ok(Json::String(self.string_body()?))
            }
            Some(b't') if self.literal("true") => Ok(Json::Bool(true)),
            Some(b'f') if self.literal("false") => Ok(Json::Bool(false)),
            Some(b'n') if self.literal("null") => Ok(Json::Null),
            Some(_) => match self.number()? {
                Some(n) => Ok(Json::Number(n)),
                None => Err(self.fail("expected a JSON value")),
            },
        }
    }

    fn container(&mut self, depth: usize, close: u8) -> Result<Json, String> {
        if depth >= MAX_DEPTH {
            return Err(self.fail("nested too deeply"));
        }
        let object = close == b'}';
        let mut items = Vec::new();
        let mut members = Vec::new();
        self.skip_space();
        if self.peek() == Some(close) {
            self.p += 1;
        } else {
            loop {
                self.skip_space();
                let mut key = String::new();
                if object {
                    if self.peek() != Some(b'"') {
                        return Err(self.fail("expected a member name in quotes"));
                    }
                    self.p += 1;
                    key = self.string_body()?;
                    self.skip_space();
                    if self.peek() != Some(b':') {
                        return Err(self.fail("expected ':' after a member name"));
                    }
                    self.p += 1;
                }
                let v = self.value(depth + 1)?;
                if object {
                    members.push((key, v));
                } else {
                    items.push(v);
                }
                self.skip_space();
                match self.peek() {
                    Some(b',') => self.p += 1,
                    Some(c) if c == close => {
                        self.p += 1;
                        break;
                    }
                    _ => return Err(self.fail(if object { "expected ',' or '}'" } else { "expected ',' or ']'" })),
                }
            }
        }
        Ok(if object { Json::Object(members) } else { Json::Array(items) })
    }

    fn hex4(&mut self) -> Result<u32, String> {
        if self.s.len() - self.p < 4 {
            return Err(self.fail("bad \\u escape"));
        }
        let mut v = 0u32;
        for _ in 0..4 {
            let d = (self.s[self.p] as char).to_digit(16).ok_or_else(|| self.fail("bad \\u escape"))?;
            self.p += 1;
            v = v * 16 + d;
        }
        Ok(v)
    }

    /// After the opening quote. Bytes outside escapes are kept as they are
    /// (invalid UTF-8 is replaced: such a name matches no rig name anyway).
    fn string_body(&mut self) -> Result<String, String> {
        let mut out: Vec<u8> = Vec::new();
        loop {
            let c = match self.peek() {
                None => return Err(self.fail("unterminated string")),
                Some(c) => c,
            };
            self.p += 1;
            match c {
                b'"' => return Ok(String::from_utf8_lossy(&out).into_owned()),
                c if c < 0x20 => return Err(self.fail("control character in a string")),
                b'\\' => {
                    let e = self.peek().ok_or_else(|| self.fail("unterminated escape"))?;
                    self.p += 1;
                    match e {
                        b'"' | b'\\' | b'/' => out.push(e),
                        b'b' => out.push(8),
                        b'f' => out.push(12),
                        b'n' => out.push(b'\n'),
                        b'r' => out.push(b'\r'),
                        b't' => out.push(b'\t'),
                        b'u' => {
                            let mut cp = self.hex4()?;
                            if (0xD800..=0xDBFF).contains(&cp) {
                                if !self.literal("\\u") {
                                    return Err(self.fail("unpaired UTF-16 surrogate in a \\u escape"));
                                }
                                let low = self.hex4()?;
                                if !(0xDC00..=0xDFFF).contains(&low) {
                                    return Err(self.fail("unpaired UTF-16 surrogate in a \\u escape"));
                                }
                                cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
                            } else if (0xDC00..=0xDFFF).contains(&cp) {
                                return Err(self.fail("unpaired UTF-16 surrogate in a \\u escape"));
                            }
                            let ch = char::from_u32(cp).ok_or_else(|| self.fail("bad \\u escape"))?;
                            let mut buf = [0u8; 4];
                            out.extend_from_slice(ch.encode_utf8(&mut buf).as_bytes());
                        }
                        _ => return Err(self.fail("unknown escape in a string")),
                    }
                }
                c => out.push(c),
            }
        }
    }

    /// The JSON number grammar checked by hand (`str::parse::<f64>` alone
    /// would also take "inf", "NaN" or "+1"). None: not a number here.
    fn number(&mut self) -> Result<Option<f64>, String> {
        let s = self.s;
        let digits = |mut q: usize| {
            while q < s.len() && s[q].is_ascii_digit() {
                q += 1;
            }
            q
        };
        let mut q = self.p;
        if s.get(q) == Some(&b'-') {
            q += 1;
        }
        match s.get(q) {
            Some(b'0') => q += 1,
            Some(b'1'..=b'9') => q = digits(q),
            _ => return Ok(None),
        }
        if s.get(q) == Some(&b'.') {
            q += 1;
            if !s.get(q).map_or(false, u8::is_ascii_digit) {
                return Ok(None);
            }
            q = digits(q);
        }
        if matches!(s.get(q), Some(b'e' | b'E')) {
            q += 1;
            if matches!(s.get(q), Some(b'+' | b'-')) {
                q += 1;
            }
            if !s.get(q).map_or(false, u8::is_ascii_digit) {
                return Ok(None);
            }
            q = digits(q);
        }
        if q - self.p >= 64 {
            return Ok(None); // no real weight or time needs 64 digits (as json.c)
        }
        // ASCII by construction; f64 parsing is correctly rounded, like strtod.
        let text = std::str::from_utf8(&s[self.p..q]).expect("ASCII digits");
        let v = text.parse::<f64>().map_err(|_| self.fail("bad number"))?;
        self.p = q;
        Ok(Some(v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_and_errors() {
        let v = parse(br#"{"a": [1, -2.5e1, true, null, "x\u00e9\ud83d\ude00"], "a": 3}"#).unwrap();
        assert_eq!(v.get("a"), Some(&Json::Number(3.0)));
        assert!(parse(b"[1,]").unwrap_err().contains("expected a JSON value"));
        assert!(parse(b"01").is_err());
        assert!(parse(b"+1").is_err());
        assert!(parse(b"\"\\ud800\"").is_err());
        assert!(parse(&[b'['; 100]).unwrap_err().contains("nested too deeply"));
        assert!(parse(b"{\n \"a\" 1}").unwrap_err().starts_with("line 2, column 6"));
    }
}
