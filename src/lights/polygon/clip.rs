//! Clipping a polygon against the horizon of a shading point: the half-space
//! `normal . p >= 0` (positions relative to the shading point), by Sutherland-Hodgman
//! for a convex polygon. Each output vertex carries whether the edge leaving it lies on
//! the light (`true`) or on the horizon plane (`false`): an edge on the horizon projects
//! to an arc of the fixed horizon great circle, which does not move with the shading
//! point (no Reynolds term, `proofs/polygon-lights.md` Sec. 4).

use super::boundary::dot;

/// A clipped polygon: vertices relative to the shading point and, per vertex, whether the
/// edge to the next vertex is an edge of the light.
pub type ClippedPolygon = Vec<([f64; 3], bool)>;

/// `polygon` (vertices relative to the shading point, each with its outgoing edge's
/// flag) clipped to `normal . p >= 0`; empty when fewer than three vertices remain.
pub fn clip_to_horizon(polygon: &[([f64; 3], bool)], normal: [f64; 3]) -> ClippedPolygon {
    let mut out = Vec::with_capacity(polygon.len() + 2);
    let s: Vec<f64> = polygon.iter().map(|(p, _)| dot(*p, normal)).collect();
    for i in 0..polygon.len() {
        let j = (i + 1) % polygon.len();
        let ((p, on_light), q) = (polygon[i], polygon[j].0);
        let (sp, sq) = (s[i], s[j]);
        let crossing = || {
            let t = sp / (sp - sq);
            std::array::from_fn(|k| p[k] + t * (q[k] - p[k]))
        };
        if sp >= 0.0 {
            out.push((p, on_light));
            if sq < 0.0 {
                out.push((crossing(), false));
            }
        } else if sq >= 0.0 {
            out.push((crossing(), on_light));
        }
    }
    if out.len() < 3 {
        out.clear();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square across the plane z = 0 keeps its upper half, with one horizon edge.
    #[test]
    fn square_across_the_horizon() {
        let sq: Vec<([f64; 3], bool)> = [
            [1.0, -1.0, -1.0],
            [1.0, 1.0, -1.0],
            [1.0, 1.0, 1.0],
            [1.0, -1.0, 1.0],
        ]
        .map(|p| (p, true))
        .to_vec();
        let c = clip_to_horizon(&sq, [0.0, 0.0, 1.0]);
        assert_eq!(c.len(), 4);
        assert!(c.iter().all(|(p, _)| p[2] >= 0.0));
        assert_eq!(c.iter().filter(|(_, on)| !on).count(), 1);
        assert!(clip_to_horizon(&sq, [1.0, 0.0, 0.0]).len() == 4);
        assert!(clip_to_horizon(&sq, [-1.0, 0.0, 0.0]).is_empty());
    }
}
