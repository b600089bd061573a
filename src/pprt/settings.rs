//! What a precomputation is asked to do: band limits, visibility, rays
//! ([`TransferSettings`]), and how much the planner may drop ([`Planning`]).

use crate::error::{Error, Result};

/// How visibility enters the transfer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Visibility {
    /// Ray-cast visibility and its triple product per vertex (PSH (54)-(56)).
    Rays,
    /// Only the tangent plane occludes: one fixed shadowing matrix in the shading frame
    /// (`proofs/tangent-plane-visibility.md`).
    TangentPlane,
    /// No shadows at all.
    Off,
}

/// Settings of the precomputation ([`TransferSettings::new`], or [`Default`] and its
/// fields).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct TransferSettings {
    /// Band limit of the transfer (`l <= l_low`).
    pub l_low: usize,
    /// Band limit of the high orders by convolution (`l_low < l <= l_high`,
    /// [`super::stages::reflected_radiance`]); `None` (or `l_low`): no high orders.
    pub l_high: Option<usize>,
    /// Visibility rays per vertex (quasi-uniform Fibonacci directions).
    pub rays: usize,
    /// The visibility asked for. A plan within a tolerance replaces [`Visibility::Rays`]
    /// by [`Visibility::TangentPlane`] when that is exact (one convex object).
    pub visibility: Visibility,
}

impl Default for TransferSettings {
    /// `l_low` 4, `l_high` 9, 256 rays, ray-cast shadows: the render job's defaults.
    fn default() -> Self {
        Self {
            l_low: 4,
            l_high: Some(9),
            rays: 256,
            visibility: Visibility::Rays,
        }
    }
}

/// Largest `l_low`: the transfer matrices hold `(l_low+1)^4` entries per material
/// channel and the visibility triple product costs `O(l_low^5)` per vertex.
pub const MAX_L_LOW: usize = 20;

/// Largest `l_high`: the projection of the materials' high orders grows like
/// `l_high^3.4` (the built-in scene on 2 vCPUs: 3 s at 9, 45 s at 20, 450 s at 32).
pub const MAX_L_HIGH: usize = 24;

impl TransferSettings {
    /// The settings of these band limits, rays and visibility.
    pub const fn new(
        l_low: usize,
        l_high: Option<usize>,
        rays: usize,
        visibility: Visibility,
    ) -> Self {
        Self {
            l_low,
            l_high,
            rays,
            visibility,
        }
    }

    /// Errors: `l_low` outside `2..=MAX_L_LOW`, `l_high` below `l_low` or above
    /// [`MAX_L_HIGH`], no rays with ray-cast visibility. Cheap: run it before any
    /// projection.
    pub fn check(&self) -> Result<()> {
        let l = self.l_low;
        if !(2..=MAX_L_LOW).contains(&l)
            || (self.visibility == Visibility::Rays && self.rays == 0)
            || self.l_high.is_some_and(|h| !(l..=MAX_L_HIGH).contains(&h))
        {
            return Err(Error::invalid(
                "transfer settings",
                format!(
                    "l_low {l}, l_high {}, {} rays",
                    high_orders_number(self.l_high),
                    self.rays
                ),
                format!(
                    "2 <= l_low <= {MAX_L_LOW}, l_low <= l_high <= {MAX_L_HIGH} (or l_high 0: \
                     no high orders), and rays > 0 with shadows"
                ),
            ));
        }
        Ok(())
    }

    /// The band limit the environment is projected to: the high orders' `l_high`, at least
    /// `l_low` (the one place it is worked out: the render job, scene files and the plan).
    pub fn environment_lmax(&self) -> usize {
        self.l_high.unwrap_or(0).max(self.l_low)
    }

    /// The high orders' band limit when there are high orders (`l_high > l_low`).
    pub fn high_orders(&self) -> Option<usize> {
        self.l_high.filter(|&h| h > self.l_low)
    }

    /// Whether the settings ask for shadows at all.
    pub fn shadows(&self) -> bool {
        self.visibility != Visibility::Off
    }
}

/// `l_high` as scene files, the command line and reports write it: 0 for no high orders.
pub fn high_orders_number(l_high: Option<usize>) -> usize {
    l_high.unwrap_or(0)
}

/// `l_high` from the number of scene files and the command line: 0 for no high orders.
pub fn high_orders_from_number(l_high: usize) -> Option<usize> {
    (l_high != 0).then_some(l_high)
}

/// How much the planner may drop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Planning {
    /// Nothing: full Stokes vectors, the visibility asked for, every nonzero entry, every
    /// high order up to `l_high` (`psh render --no-plan`).
    Full,
    /// Whatever stays within this relative tolerance, in `(0, 1)`.
    Tolerance(f64),
}

impl Planning {
    /// The tolerance, `None` for [`Planning::Full`].
    pub fn tolerance(self) -> Option<f64> {
        match self {
            Planning::Full => None,
            Planning::Tolerance(t) => Some(t),
        }
    }
}
