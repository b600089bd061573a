//! What the argument of a light field means: the direction towards the light's source
//! (incident radiance, an environment as seen from a point: psh's maps and projections)
//! or the light's direction of travel (exitant radiance: the output of a pBRDF or a
//! transfer, and every field polarsh stores). Coefficient vectors and matrices carry it
//! like a Stokes vector carries its frame (PSH Sec. 4.2.1): conversion is explicit
//! ([`super::PshVector::converted`]), combining the two is a [`crate::Error`].

use crate::error::{Error, Result};

/// The meaning of a field's argument direction `w`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FieldArgument {
    /// `w` points towards the light's source; Stokes frames with `z = w` (against the
    /// light's travel). psh's environment maps, projections and pBRDF inputs.
    TowardsSource,
    /// `w` is the light's direction of travel; Stokes frames with `z = w`. pBRDF and
    /// transfer outputs, and polarsh's `.npz` files.
    Travel,
}

crate::named_enum!(FieldArgument, "field argument", {
    TowardsSource => "towards-source",
    Travel => "travel",
});

impl FieldArgument {
    /// The other convention.
    pub fn reversed(self) -> Self {
        match self {
            FieldArgument::TowardsSource => FieldArgument::Travel,
            FieldArgument::Travel => FieldArgument::TowardsSource,
        }
    }

    /// Error unless `given` is `self`: `what` (e.g. "PSH vector") met an operand that
    /// expects `self`, described by `expected_by` (e.g. "the matrix's input").
    pub fn expect(self, given: FieldArgument, what: &'static str, expected_by: &str) -> Result<()> {
        if given == self {
            return Ok(());
        }
        Err(Error::invalid(
            what,
            format!("indexed by the {} direction", given.name()),
            format!(
                "{expected_by} is indexed by the {} direction; convert explicitly \
                 (PshVector::converted / with_input)",
                self.name()
            ),
        ))
    }
}
