//! Fast fluid solver: the discretisation and PIMPLE algorithm of the reference solver (see the
//! module doc of `spillage_reference::fluid`, spec fluid-dem-model.md §8), engineered for speed:
//!
//! - struct-of-arrays link and boundary geometry ([`layout`]), precomputed once and updated in
//!   place for the rotor-zone faces when the rotor turns; the sliding-interface overlaps are a
//!   1-D θ merge per shared z layer, O(faces) per step ([`interface`]);
//! - assembly as per-link kernels followed by per-cell gathers over the cell's links in
//!   ascending link order ([`assembly`]): no scatter, no atomics, bit-identical results on any
//!   number of threads; work arrays are sized once, so the time loop does not allocate (except
//!   the `StepReport` values and a rebuild when the link count grows);
//! - pressure by flexible CG preconditioned with a K-cycle aggregation AMG (multicolour
//!   Gauss–Seidel smoothing; the hierarchy's values follow every pressure matrix, its
//!   aggregation is rebuilt only when the overlap links change the pattern), momentum by
//!   Jacobi-BiCGStab ([`crate::linear`]), both with OpenFOAM-normalised residual tolerances ([`FastSettings`]).

//!
//! One step ([`FastFluid`], `pimple.rs`) is a pipeline over free kernels, one module per stage:
//! [`starting_values`] (step 3), [`momentum`] (steps 4a–c), [`pressure_corrector`] (step 4d),
//! [`diagnostics`], [`turbulence`] and [`finish_step`] (step 5); they read [`step_inputs`] and write the
//! [`buffers`] of the step. [`assembly`] holds the shared gradient and interpolation kernels.

pub mod assembly;
pub mod buffers;
pub mod diagnostics;
pub mod finish_step;
pub mod interface;
pub mod layout;
pub mod momentum;
mod pimple;
pub mod pressure_corrector;
pub mod settings;
pub mod starting_values;
pub mod step_inputs;
pub mod turbulence;

pub use pimple::FastFluid;
pub use settings::{FastSettings, SolveCounts};
