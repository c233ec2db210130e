//! Shared decoding of fuzz input into ellipses: raw doubles (any bit pattern: NaN, infinities,
//! subnormals, huge and tiny values) or, half of the time, doubles built to sit near the hard
//! cases (tangency, identical, thin, far from the origin).

use geofeas::Ellipse;

pub fn f64s(data: &[u8]) -> impl Iterator<Item = f64> + '_ {
    data.chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
}

/// Two ellipses from the input: the first 80 bytes as raw doubles, or (when the first byte is
/// odd) a structured pair derived from them.
pub fn pair(data: &[u8]) -> Option<(Ellipse, Ellipse)> {
    let v: Vec<f64> = f64s(data).take(10).collect();
    if v.len() < 10 {
        return None;
    }
    let raw = (
        Ellipse::new(v[0], v[1], v[2], v[3], v[4]),
        Ellipse::new(v[5], v[6], v[7], v[8], v[9]),
    );
    if data[0] & 1 == 0 {
        return Some(raw);
    }
    // structured: b is a derived from a by small relative changes (near-identical and
    // near-tangent configurations the raw bytes almost never reach)
    let unit = |x: f64| if x.is_finite() { x.fract() } else { 0.0 };
    let a = Ellipse::new(
        unit(v[0]) * 1e6,
        unit(v[1]) * 1e6,
        1.0 + unit(v[2]).abs() * 10.0,
        1.0 + unit(v[3]).abs(),
        unit(v[4]) * 7.0,
    );
    let scale = 10f64.powi(-((data[1] % 17) as i32));
    let b = Ellipse::new(
        a.x0 + unit(v[5]) * a.rx * 2.0 * (1.0 + scale),
        a.y0 + unit(v[6]) * scale,
        a.rx * (1.0 + unit(v[7]) * scale),
        a.ry * (1.0 + unit(v[8]) * scale),
        a.phi + unit(v[9]) * scale,
    );
    Some((a, b))
}
