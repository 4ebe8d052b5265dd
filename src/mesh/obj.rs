//! Wavefront OBJ: reading `v` and `f` lines (in parallel) and writing plain OBJ.
//!
//! Read: `v x y z` (extra values such as `w` or colours are ignored), `f` with `v`, `v/vt`,
//! `v//vn` or `v/vt/vn` corners and negative (relative) indices; polygons are split into
//! a fan from their first corner; `o` and `g` lines are counted, and their names and those
//! of `usemtl` lines kept as the faces' groups ([`super::groups`]: the materials where the
//! file has any, else the groups and objects); everything else (`vt`, `vn`, `l`, `p`,
//! comments) is skipped. Vertices keep the order of the file, so
//! `puppet skeleton` output lines up with the input.
//!
//! The text is cut at line ends into a few chunks per core, parsed in parallel by a byte
//! scanner (integers and the usual decimal numbers exactly, on the spot; anything unusual
//! through `f64::from_str`). A chunk cannot know how many vertices come before it, so
//! relative indices are resolved, and range checks settled, once every chunk is done: each
//! chunk keeps the lines where its demand on the vertices before it first grows, and the
//! first error of the file (in line order) is the one reported.

use super::groups::FaceGroups;
use super::soup::Soup;
use super::MeshError;
use glam::DVec3;
use rayon::prelude::*;
use std::io::Write;

/// Parses OBJ text into a triangle soup (indices checked, coordinates not yet).
///
/// # Errors
/// [`MeshError::NotText`] for a NUL byte or invalid UTF-8, [`MeshError::Syntax`] naming the
/// first malformed line, [`MeshError::Parse`] for a file with nothing but white space.
pub fn parse(bytes: &[u8]) -> Result<Soup, MeshError> {
    let chunks = split_lines(bytes, 4 * rayon::current_num_threads().max(1));
    // Text checks, chunk by chunk; the first problem in file order wins.
    let checks: Vec<Result<(), MeshError>> = chunks
        .par_iter()
        .map(|&(start, end)| {
            let chunk = &bytes[start..end];
            if chunk.contains(&0) {
                let pos = chunk.iter().position(|&b| b == 0).unwrap_or(0);
                return Err(MeshError::NotText(format!(
                    "NUL byte at offset {}",
                    start + pos
                )));
            }
            std::str::from_utf8(chunk).map(|_| ()).map_err(|e| {
                MeshError::NotText(format!("invalid UTF-8 at byte {}", start + e.valid_up_to()))
            })
        })
        .collect();
    checks.into_iter().collect::<Result<Vec<()>, _>>()?;
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(MeshError::Parse("the file is empty".into()));
    }
    let parts: Vec<Chunk> = chunks
        .par_iter()
        .map(|&(start, end)| parse_chunk(&bytes[start..end]))
        .collect();
    // Lines and vertices before each chunk; the first error in file order.
    let (mut lines_before, mut vertices_before) = (0usize, 0usize);
    let mut offsets = Vec::with_capacity(parts.len());
    for part in &parts {
        offsets.push(vertices_before);
        if let Some((line, message)) = part.first_error(vertices_before) {
            return Err(MeshError::Syntax {
                line: lines_before + line,
                message,
            });
        }
        lines_before += part.lines;
        vertices_before += part.positions.len();
    }
    let mut soup = assemble(&parts, &offsets, vertices_before)?;
    soup.groups = face_groups(&parts);
    Ok(soup)
}

/// The faces' groups: by `usemtl` where the file has any, else by `g` and `o` names.
fn face_groups(parts: &[Chunk]) -> Option<FaceGroups> {
    if parts.iter().all(|p| p.names.is_empty()) {
        return None;
    }
    let material = parts.iter().any(|p| p.names.iter().any(|n| n.material));
    let mut current: Option<&str> = None;
    let mut per_face = Vec::new();
    for part in parts {
        let mut events = part
            .names
            .iter()
            .filter(|n| n.material == material)
            .peekable();
        for t in 0..part.triangles.len() as u32 {
            while let Some(e) = events.next_if(|e| e.before <= t) {
                current = Some(&e.name);
            }
            per_face.push(current);
        }
        for e in events {
            current = Some(&e.name);
        }
    }
    FaceGroups::from_names(per_face.into_iter())
}

/// Joins the chunks (in parallel), resolving relative indices.
fn assemble(parts: &[Chunk], offsets: &[usize], vertices: usize) -> Result<Soup, MeshError> {
    let triangles: usize = parts.iter().map(|p| p.triangles.len()).sum();
    let mut soup = Soup {
        loose_comments: 0,
        positions: vec![DVec3::ZERO; vertices],
        triangles: vec![[0; 3]; triangles],
        objects: parts.iter().map(|p| p.objects).sum::<usize>().max(1),
        groups: None,
        skin: None,
        unread_skin: None,
        borrowed_weights: 0,
    };
    let mut jobs = Vec::with_capacity(parts.len());
    let (mut ps, mut ts) = (&mut soup.positions[..], &mut soup.triangles[..]);
    for (part, &offset) in parts.iter().zip(offsets) {
        let (p, rest_p) = ps.split_at_mut(part.positions.len());
        let (t, rest_t) = ts.split_at_mut(part.triangles.len());
        jobs.push((part, offset, p, t));
        (ps, ts) = (rest_p, rest_t);
    }
    jobs.into_par_iter().for_each(|(part, offset, p, t)| {
        p.copy_from_slice(&part.positions);
        t.copy_from_slice(&part.triangles);
        for &(tri, corner, local) in &part.relative {
            // Checked against the records: offset + local is a vertex.
            t[tri as usize][corner as usize] = (offset as i64 + local) as u32;
        }
    });
    Ok(soup)
}

/// `[start, end)` byte ranges of about `pieces` chunks, each ending after a `\n` (the last at
/// the end of the text).
fn split_lines(bytes: &[u8], pieces: usize) -> Vec<(usize, usize)> {
    // Small files are one chunk: threads cost more than they save.
    let pieces = if bytes.len() < 1 << 20 { 1 } else { pieces };
    let mut out = Vec::with_capacity(pieces);
    let mut start = 0;
    for k in 1..=pieces {
        let target = bytes.len() * k / pieces;
        if target <= start {
            continue;
        }
        let end = if k == pieces {
            bytes.len()
        } else {
            match bytes[target..].iter().position(|&b| b == b'\n') {
                Some(p) => target + p + 1,
                None => bytes.len(),
            }
        };
        out.push((start, end));
        start = end;
        if start == bytes.len() {
            break;
        }
    }
    if out.is_empty() {
        out.push((0, bytes.len()));
    }
    out
}

/// A line where a chunk's need for vertices before it first grew: `need` vertices must
/// come before the chunk for the line's index `index` to exist, with `so_far` vertices of
/// the chunk before the line.
#[derive(Clone, Copy, Debug)]
struct Demand {
    need: usize,
    line: usize,
    index: i64,
    so_far: usize,
}

/// A name line: what it names and where.
struct Name {
    /// Triangles of the chunk before the line.
    before: u32,
    /// A `usemtl` (else `g` or `o`).
    material: bool,
    name: String,
}

/// One chunk parsed.
#[derive(Default)]
struct Chunk {
    positions: Vec<DVec3>,
    /// Triangles; corners given relative to the end are filled in by `assemble`.
    triangles: Vec<[u32; 3]>,
    /// Relative corners: triangle, corner, index counted from the chunk's first vertex
    /// (negative: a vertex of an earlier chunk).
    relative: Vec<(u32, u8, i64)>,
    objects: usize,
    /// `g`, `o` and `usemtl` names, in order.
    names: Vec<Name>,
    /// Lines in the chunk.
    lines: usize,
    /// The first malformed line (from 1 in the chunk) and what is wrong, if any; parsing
    /// stopped there.
    error: Option<(usize, String)>,
    /// Lines whose demand on the vertices before the chunk exceeds every earlier line's.
    demands: Vec<Demand>,
}

impl Chunk {
    /// The first error of the chunk when `before` vertices precede it.
    fn first_error(&self, before: usize) -> Option<(usize, String)> {
        let range = self.demands.iter().find(|d| d.need > before).map(|d| {
            (
                d.line,
                format!(
                    "vertex index {} is out of range (the file has {} vertices so far)",
                    d.index,
                    before + d.so_far
                ),
            )
        });
        match (range, &self.error) {
            (Some(r), Some(e)) => Some(if r.0 <= e.0 { r } else { e.clone() }),
            (r, e) => r.or_else(|| e.clone()),
        }
    }
}

/// White space inside a line, as `split_ascii_whitespace` sees it.
#[inline]
fn is_blank(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\x0c')
}

/// A cursor over one chunk of text.
struct Cursor<'a> {
    text: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    /// Skips blanks; true when a word follows on this line.
    #[inline]
    fn word_follows(&mut self) -> bool {
        while self.at < self.text.len() && is_blank(self.text[self.at]) {
            self.at += 1;
        }
        self.at < self.text.len() && self.text[self.at] != b'\n'
    }

    /// The word at the cursor (up to white space), consumed.
    #[inline]
    fn word(&mut self) -> &'a [u8] {
        let start = self.at;
        while self.at < self.text.len() && !self.text[self.at].is_ascii_whitespace() {
            self.at += 1;
        }
        &self.text[start..self.at]
    }

    /// Does a word end at `at` (white space or the end)?
    #[inline]
    fn word_ends(&self, at: usize) -> bool {
        at >= self.text.len() || self.text[at].is_ascii_whitespace()
    }

    /// The rest of the line, trimmed (the line's end is left for [`Cursor::next_line`]).
    fn rest(&mut self) -> String {
        let start = self.at;
        let end = self.text[start..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(self.text.len(), |p| start + p);
        self.at = end;
        String::from_utf8_lossy(&self.text[start..end])
            .trim()
            .to_string()
    }

    /// Moves past the end of the line.
    #[inline]
    fn next_line(&mut self) {
        match self.text[self.at..].iter().position(|&b| b == b'\n') {
            Some(p) => self.at += p + 1,
            None => self.at = self.text.len(),
        }
    }

    /// A number as `f64::from_str` reads it: `fast_float2` reads it in place (exactly, as
    /// the standard library does), the standard library when the word is anything unusual.
    #[inline]
    fn number(&mut self) -> Result<f64, String> {
        if let Ok((value, len)) = fast_float2::parse_partial::<f64, _>(&self.text[self.at..]) {
            if len > 0 && self.word_ends(self.at + len) {
                self.at += len;
                return Ok(value);
            }
        }
        let word = self.word();
        std::str::from_utf8(word)
            .ok()
            .and_then(|w| w.parse().ok())
            .ok_or_else(|| format!("'{}' is not a number", text(word)))
    }

    /// A face corner's vertex index (`v`, `v/vt`, `v//vn`, `v/vt/vn`) as `i64::from_str`
    /// reads the part before the first slash.
    #[inline]
    fn index(&mut self) -> Result<i64, String> {
        let t = self.text;
        let start = self.at;
        let mut i = start;
        let negative = t[i] == b'-';
        if negative || t[i] == b'+' {
            i += 1;
        }
        let digits = i;
        let mut v: i64 = 0;
        while i < t.len() && t[i].is_ascii_digit() && i - digits < 18 {
            v = v * 10 + i64::from(t[i] - b'0');
            i += 1;
        }
        let plain = i > digits && (i >= t.len() || t[i] == b'/' || t[i].is_ascii_whitespace());
        let word = self.word();
        if plain {
            return Ok(if negative { -v } else { v });
        }
        let first = word.split(|&b| b == b'/').next().unwrap_or(b"");
        std::str::from_utf8(first)
            .ok()
            .and_then(|w| w.parse().ok())
            .ok_or_else(|| format!("'{}' is not a vertex index", text(word)))
    }
}

fn parse_chunk(text: &[u8]) -> Chunk {
    // Room for the most a chunk can hold in the usual forms (a `v` line takes at least 8
    // bytes, a triangle 8): untouched capacity costs no memory, growing costs copies.
    let mut c = Chunk {
        positions: Vec::with_capacity(text.len() / 8),
        triangles: Vec::with_capacity(text.len() / 8),
        ..Chunk::default()
    };
    let mut corners: Vec<(i64, bool)> = Vec::new();
    let mut cur = Cursor { text, at: 0 };
    let mut line = 0;
    while cur.at < text.len() {
        line += 1;
        let outcome = if cur.word_follows() {
            match cur.word() {
                b"v" => vertex(&mut cur, &mut c),
                b"f" => face(&mut cur, &mut c, line, &mut corners),
                b"o" | b"g" => {
                    c.objects += 1;
                    let name = cur.rest();
                    c.names.push(Name {
                        before: c.triangles.len() as u32,
                        material: false,
                        name,
                    });
                    Ok(())
                }
                b"usemtl" => {
                    let name = cur.rest();
                    c.names.push(Name {
                        before: c.triangles.len() as u32,
                        material: true,
                        name,
                    });
                    Ok(())
                }
                _ => Ok(()),
            }
        } else {
            Ok(())
        };
        if let Err(message) = outcome {
            c.error = Some((line, message));
            break;
        }
        cur.next_line();
    }
    c.lines = line;
    c
}

/// Text of a word for a message (the chunk is valid UTF-8 and words end at ASCII bytes).
fn text(word: &[u8]) -> String {
    String::from_utf8_lossy(word).into_owned()
}

fn vertex(cur: &mut Cursor, c: &mut Chunk) -> Result<(), String> {
    let mut xyz = [0.0f64; 3];
    for (k, slot) in xyz.iter_mut().enumerate() {
        if !cur.word_follows() {
            return Err(format!("vertex has {k} coordinates, expected 3"));
        }
        *slot = cur.number()?;
    }
    c.positions.push(DVec3::from_array(xyz));
    Ok(())
}

fn face(
    cur: &mut Cursor,
    c: &mut Chunk,
    line: usize,
    corners: &mut Vec<(i64, bool)>,
) -> Result<(), String> {
    corners.clear();
    let so_far = c.positions.len();
    while cur.word_follows() {
        let index = cur.index()?;
        // Positive: the vertex index - 1 of the file, which needs index - so_far vertices
        // before the chunk. Negative: counted back from the latest vertex.
        let (value, relative, need) = if index > 0 {
            let need = (index as u64).saturating_sub(so_far as u64) as usize;
            (index - 1, false, need)
        } else if index < 0 {
            let local = so_far as i64 + index;
            (local, true, if local < 0 { (-local) as usize } else { 0 })
        } else {
            (0, false, usize::MAX)
        };
        if need > c.demands.last().map_or(0, |d| d.need) {
            c.demands.push(Demand {
                need,
                line,
                index,
                so_far,
            });
        }
        corners.push((value, relative));
    }
    if corners.len() < 3 {
        return Err(format!(
            "face has {} vertices, expected at least 3",
            corners.len()
        ));
    }
    for k in 1..corners.len() - 1 {
        let tri = c.triangles.len() as u32;
        let mut t = [0u32; 3];
        for (slot, &(value, relative)) in
            [corners[0], corners[k], corners[k + 1]].iter().enumerate()
        {
            if relative {
                c.relative.push((tri, slot as u8, value));
            } else {
                t[slot] = value.clamp(0, u32::MAX as i64) as u32;
            }
        }
        c.triangles.push(t);
    }
    Ok(())
}

/// Writes `positions` and 1-based triangles as a plain OBJ, each number in the shortest
/// form that reads back to the same `f64`. Lines are formatted in parallel chunks.
pub fn write(
    out: &mut dyn Write,
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    header: &str,
) -> std::io::Result<()> {
    let mut head = String::new();
    for line in header.lines() {
        head.push_str("# ");
        head.push_str(line);
        head.push('\n');
    }
    out.write_all(head.as_bytes())?;
    const CHUNK: usize = 1 << 14;
    let write_chunks = |out: &mut dyn Write, chunks: Vec<Vec<u8>>| -> std::io::Result<()> {
        for c in chunks {
            out.write_all(&c)?;
        }
        Ok(())
    };
    for block in positions.chunks(CHUNK * 16) {
        let chunks: Vec<Vec<u8>> = block
            .par_chunks(CHUNK)
            .map(|ps| {
                let mut buf = Vec::with_capacity(ps.len() * 40);
                let mut f = zmij::Buffer::new();
                for p in ps {
                    buf.extend_from_slice(b"v");
                    for x in p.to_array() {
                        buf.push(b' ');
                        buf.extend_from_slice(f.format(x).as_bytes());
                    }
                    buf.push(b'\n');
                }
                buf
            })
            .collect();
        write_chunks(out, chunks)?;
    }
    for block in triangles.chunks(CHUNK * 16) {
        let chunks: Vec<Vec<u8>> = block
            .par_chunks(CHUNK)
            .map(|ts| {
                let mut buf = Vec::with_capacity(ts.len() * 24);
                let mut f = itoa_buffer();
                for t in ts {
                    buf.extend_from_slice(b"f");
                    for &v in t {
                        buf.push(b' ');
                        buf.extend_from_slice(f.format(v as u64 + 1));
                    }
                    buf.push(b'\n');
                }
                buf
            })
            .collect();
        write_chunks(out, chunks)?;
    }
    out.flush()
}

/// Decimal digits of an unsigned integer, without allocating.
struct Digits([u8; 20]);

fn itoa_buffer() -> Digits {
    Digits([0; 20])
}

impl Digits {
    fn format(&mut self, mut v: u64) -> &[u8] {
        let mut i = self.0.len();
        loop {
            i -= 1;
            self.0[i] = b'0' + (v % 10) as u8;
            v /= 10;
            if v == 0 {
                break;
            }
        }
        &self.0[i..]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_cover_the_text_at_line_ends() {
        let text: Vec<u8> = (0..300_000)
            .flat_map(|i| format!("v {i} 0 0\n").into_bytes())
            .collect();
        let chunks = split_lines(&text, 7);
        assert_eq!(chunks[0].0, 0);
        assert_eq!(chunks.last().map(|c| c.1), Some(text.len()));
        for w in chunks.windows(2) {
            assert_eq!(w[0].1, w[1].0);
            assert_eq!(text[w[0].1 - 1], b'\n');
        }
        assert!(chunks.len() > 1);
    }

    #[test]
    fn chunked_parse_equals_one_chunk() {
        // Relative indices and line numbers across chunk boundaries.
        let mut text = String::new();
        for i in 0..200_000 {
            text.push_str(&format!("v {i} {} 0.5\n", i % 7));
            if i >= 2 {
                text.push_str("f -3 -2/4 -1//2\n");
            }
        }
        let many = parse(text.as_bytes()).expect("parses");
        let one = parse_chunk(text.as_bytes());
        assert!(one.error.is_none());
        assert_eq!(many.positions, one.positions);
        assert_eq!(many.triangles.len(), 199_998);
        for (k, t) in many.triangles.iter().enumerate() {
            let v = k as u32 + 2;
            assert_eq!(*t, [v - 2, v - 1, v]);
        }
        let bad = format!("{text}f 1 2 999999\n");
        let lines = text.lines().count();
        match parse(bad.as_bytes()) {
            Err(MeshError::Syntax { line, .. }) => assert_eq!(line, lines + 1),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn written_numbers_read_back_exactly() {
        let ps = [
            DVec3::new(0.1, -2.5e-9, 1e300),
            DVec3::new(1.0 / 3.0, 0.0, -0.0),
        ];
        let mut out = Vec::new();
        write(&mut out, &ps, &[[0, 1, 1]], "a\nb").expect("writes");
        let text = String::from_utf8(out).expect("text");
        assert!(text.starts_with("# a\n# b\nv "), "{text}");
        assert!(text.ends_with("f 1 2 2\n"), "{text}");
        let read = parse(text.as_bytes()).expect("parses");
        assert_eq!(read.positions, ps);
    }

    /// The numbers of a `v` line, or its error.
    fn numbers(word: &str) -> Result<f64, String> {
        let line = format!("v {word} 0 0\n");
        let c = parse_chunk(line.as_bytes());
        match c.error {
            Some((_, e)) => Err(e),
            None => Ok(c.positions[0].x),
        }
    }

    #[test]
    fn numbers_read_as_the_standard_library_reads_them() {
        let words = [
            "0",
            "-0",
            "+1",
            "1.",
            ".5",
            "-.5",
            "0.1",
            "3.14159",
            "-0.7749864598214286",
            "2.7456365089285715",
            "123456789012345678",
            "1234567890123456789",
            "0.000123",
            "1e5",
            "1E-5",
            "-2.5e+3",
            "1e400",
            "1e-400",
            "inf",
            "-infinity",
            "NaN",
            "nan",
            "9007199254740993",
            "0.30000000000000004",
            "1.7976931348623157e308",
            "00012.50",
            ".",
            "-",
            "e5",
            "1e",
            "1.2.3",
            "0x10",
            "1_0",
            "1,5",
        ];
        for w in words {
            let ours = numbers(w).map(f64::to_bits);
            let std = w
                .parse::<f64>()
                .map(f64::to_bits)
                .map_err(|_| format!("'{w}' is not a number"));
            assert_eq!(ours, std, "{w}");
        }
        // The shortest forms of many doubles.
        let mut x = 0.1f64;
        for _ in 0..20_000 {
            x = (x * 1.618_033_988_749_895 + 0.37).fract() * 10f64.powi((x * 40.0) as i32 - 20);
            for y in [x, -x, x * 1e-3, (x * 1e6).round()] {
                assert_eq!(numbers(&y.to_string()), Ok(y));
            }
        }
        for w in [
            "12",
            "-3",
            "+4",
            "007",
            "99999999999999999999",
            "1.5",
            "-",
            "x",
            "5x",
        ] {
            let line = format!("f {w} 1 1\n");
            let c = parse_chunk(line.as_bytes());
            let ours = match c.error {
                Some((_, e)) => Err(e),
                None => Ok(()),
            };
            let std = w
                .parse::<i64>()
                .map(|_| ())
                .map_err(|_| format!("'{w}' is not a vertex index"));
            assert_eq!(ours, std, "{w}");
        }
    }

    #[test]
    fn digits() {
        let mut d = itoa_buffer();
        for v in [0u64, 7, 10, 4_294_967_296, u64::MAX] {
            assert_eq!(d.format(v), v.to_string().as_bytes());
        }
    }
}
