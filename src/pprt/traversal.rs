//! Ray queries through a BVH of the `bvh` crate (its tree, walked here): the nearest hit
//! visits the nearer child first and skips every box that begins beyond the nearest hit
//! found so far, where the crate's iterator hands out every shape whose box the ray
//! crosses, in no order; any hit stops at the first. On the built-in scene a primary ray
//! visits about 15 nodes; the frame times moved by a few percent (`view/*` in
//! `benches/pprt.rs`, `docs/view.md`).

use bvh::aabb::Aabb;
use bvh::bvh::{Bvh, BvhNode};
use bvh::ray::Ray;

/// What a query wants: the nearest hit, or whether there is any.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Wanted {
    Nearest,
    Any,
}

/// The nearest (or, for [`Wanted::Any`], the first found) of the hits `hit` reports for
/// the shapes whose boxes `ray` crosses beyond `t_min`. `hit` tests one shape (index into
/// the shapes the tree was built over) and reports a hit beyond `t_min` only, with its
/// distance along the ray.
pub(crate) fn first_hit<H>(
    bvh: &Bvh<f64, 3>,
    ray: &Ray<f64, 3>,
    t_min: f64,
    wanted: Wanted,
    mut hit: impl FnMut(usize) -> Option<(f64, H)>,
) -> Option<H> {
    let mut best: Option<(f64, H)> = None;
    // Nodes to visit with the distance at which the ray enters their box (the root's is
    // not stored: 0).
    let mut stack = Stack::default();
    if !bvh.nodes.is_empty() {
        stack.push((0, 0.0));
    }
    while let Some((node, enter)) = stack.pop() {
        let reach = best.as_ref().map_or(f64::INFINITY, |b| b.0);
        if enter > reach {
            continue;
        }
        match &bvh.nodes[node] {
            BvhNode::Leaf { shape_index, .. } => {
                if let Some(h) = hit(*shape_index) {
                    if h.0 < reach {
                        if wanted == Wanted::Any {
                            return Some(h.1);
                        }
                        best = Some(h);
                    }
                }
            }
            BvhNode::Node {
                child_l_index,
                child_l_aabb,
                child_r_index,
                child_r_aabb,
                ..
            } => {
                // A child's entry distance, if it is crossed within [t_min, reach].
                let span = |aabb: &Aabb<f64, 3>| slab(ray, aabb, t_min, reach);
                match (span(child_l_aabb), span(child_r_aabb)) {
                    (Some(l), Some(r)) => {
                        // The nearer is popped first.
                        let (near, far) = if l <= r {
                            ((*child_l_index, l), (*child_r_index, r))
                        } else {
                            ((*child_r_index, r), (*child_l_index, l))
                        };
                        stack.push(far);
                        stack.push(near);
                    }
                    (Some(l), None) => stack.push((*child_l_index, l)),
                    (None, Some(r)) => stack.push((*child_r_index, r)),
                    (None, None) => {}
                }
            }
        }
    }
    best.map(|b| b.1)
}

/// The distance at which `ray` enters `aabb` within `[t_min, reach]`, if it crosses it
/// there (the slab test; an axis along which a slab bound gives `0 x inf` leaves the
/// interval as it is, so a ray in a box's face plane counts as crossing it).
#[inline(always)]
fn slab(ray: &Ray<f64, 3>, aabb: &Aabb<f64, 3>, t_min: f64, reach: f64) -> Option<f64> {
    let (mut t0, mut t1) = (t_min, reach);
    for k in 0..3 {
        let a = (aabb.min[k] - ray.origin[k]) * ray.inv_direction[k];
        let b = (aabb.max[k] - ray.origin[k]) * ray.inv_direction[k];
        if a.is_nan() || b.is_nan() {
            continue;
        }
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    (t0 <= t1).then_some(t0)
}

/// The nodes a query has still to visit: 64 in place (a tree as deep needs no more),
/// any beyond on the heap.
struct Stack {
    near: [(usize, f64); 64],
    len: usize,
    beyond: Vec<(usize, f64)>,
}

impl Default for Stack {
    fn default() -> Self {
        Self {
            near: [(0, 0.0); 64],
            len: 0,
            beyond: Vec::new(),
        }
    }
}

impl Stack {
    fn push(&mut self, x: (usize, f64)) {
        if self.len < self.near.len() {
            self.near[self.len] = x;
            self.len += 1;
        } else {
            self.beyond.push(x);
        }
    }

    /// The last pushed (those beyond were pushed after every one in place).
    fn pop(&mut self) -> Option<(usize, f64)> {
        self.beyond.pop().or_else(|| {
            self.len = self.len.checked_sub(1)?;
            Some(self.near[self.len])
        })
    }
}
