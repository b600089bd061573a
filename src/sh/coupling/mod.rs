//! Coupling coefficients: Wigner 3j symbols and Gaunt coefficients, and their tables.

pub(crate) mod gaunt;
pub(crate) mod gaunt_table;
pub(crate) mod wigner3j;
