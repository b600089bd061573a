//! Properties of the mathematics over random inputs (proptest): Stokes vectors and
//! Mueller transforms, optics, the polarizing filter, PSH vectors and matrices, the
//! convolution theorem, SH and Wigner D, and the Gaunt coefficients against their exact
//! oracle. One test binary (`cargo test --release --test properties`).

mod convolution_properties;
mod filter_properties;
mod gaunt_oracle;
mod optics_properties;
mod polarized_properties;
mod properties;
mod stokes_properties;
