//! The recursions in the degree: normalized associated Legendre functions and the Lambda recursion of every spin.

pub(crate) mod double_double;
pub(crate) mod lambda;
pub(crate) mod legendre;
