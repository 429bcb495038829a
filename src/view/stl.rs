//! STL meshes, ASCII and binary, read into triangles (vertex triples, the file's units).

/// Most triangles read from one file: a drawing needs far fewer, and a page must stay small.
pub const MAX_TRIANGLES: usize = 200_000;

/// Triangles of an STL file's bytes, or what is wrong with them.
pub fn parse(bytes: &[u8]) -> Result<Vec<[[f32; 3]; 3]>, String> {
    // A binary file may begin with "solid" too: its size settles which it is.
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if n.checked_mul(50).and_then(|b| b.checked_add(84)) == Some(bytes.len()) {
            return binary(bytes, n);
        }
    }
    if bytes.trim_ascii_start().starts_with(b"solid") {
        return ascii(bytes);
    }
    Err("neither an ASCII STL (starting with `solid`) nor a binary STL of consistent size".into())
}

fn check_count(n: usize) -> Result<(), String> {
    if n > MAX_TRIANGLES {
        return Err(format!(
            "{n} triangles, more than the {MAX_TRIANGLES} a drawing takes; simplify the mesh"
        ));
    }
    Ok(())
}

fn binary(bytes: &[u8], n: usize) -> Result<Vec<[[f32; 3]; 3]>, String> {
    check_count(n)?;
    let f = |o: usize| f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    let mut out = Vec::with_capacity(n);
    for t in 0..n {
        // 12 bytes of normal, then three vertices of three floats.
        let base = 84 + 50 * t + 12;
        let mut tri = [[0.0f32; 3]; 3];
        for (v, vertex) in tri.iter_mut().enumerate() {
            for (c, value) in vertex.iter_mut().enumerate() {
                *value = f(base + 12 * v + 4 * c);
            }
        }
        out.push(tri);
    }
    finite(out)
}

fn ascii(bytes: &[u8]) -> Result<Vec<[[f32; 3]; 3]>, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "an ASCII STL that is not UTF-8")?;
    let mut vertices = Vec::new();
    for (line_no, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if words.next() != Some("vertex") {
            continue;
        }
        let mut v = [0.0f32; 3];
        for value in &mut v {
            *value = words
                .next()
                .and_then(|w| w.parse().ok())
                .ok_or_else(|| format!("line {}: a vertex needs three numbers", line_no + 1))?;
        }
        vertices.push(v);
        check_count(vertices.len() / 3)?;
    }
    if vertices.len() % 3 != 0 {
        return Err(format!(
            "{} vertices, not a whole number of triangles",
            vertices.len()
        ));
    }
    finite(vertices.chunks(3).map(|c| [c[0], c[1], c[2]]).collect())
}

fn finite(triangles: Vec<[[f32; 3]; 3]>) -> Result<Vec<[[f32; 3]; 3]>, String> {
    if triangles.iter().flatten().flatten().any(|v| !v.is_finite()) {
        return Err("a vertex is not a finite number".into());
    }
    if triangles.is_empty() {
        return Err("no triangles".into());
    }
    Ok(triangles)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A binary STL of the given triangles.
    pub(crate) fn binary_stl(triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
        let mut out = vec![b's'; 80];
        out.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
        for t in triangles {
            out.extend_from_slice(&[0u8; 12]);
            for v in t {
                for c in v {
                    out.extend_from_slice(&c.to_le_bytes());
                }
            }
            out.extend_from_slice(&[0u8; 2]);
        }
        out
    }

    const TRI: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.5]];

    #[test]
    fn ascii_and_binary_read_alike() {
        let ascii = "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 2 0.5\n  endloop\n endfacet\nendsolid t\n";
        assert_eq!(parse(ascii.as_bytes()).unwrap(), vec![TRI]);
        assert_eq!(parse(&binary_stl(&[TRI, TRI])).unwrap(), vec![TRI, TRI]);
    }

    #[test]
    fn broken_files_are_refused() {
        assert!(parse(b"solid x\nvertex 1 2\nendsolid").is_err());
        assert!(parse(b"not an stl").is_err());
        let mut bad = binary_stl(&[TRI]);
        bad.pop();
        assert!(parse(&bad).is_err());
        let nan = [[f32::NAN, 0.0, 0.0], TRI[1], TRI[2]];
        assert!(parse(&binary_stl(&[nan])).is_err());
    }
}
