//! Cylindrical (r, θ, z) block generators about the z axis.
