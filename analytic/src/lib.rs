//! `spillage-analytic`: closed-form and semi-analytic answers the spillage solvers are checked
//! against.
//!
//! This crate is the project's independent referee. It depends on no other workspace crate and
//! derives every answer from the equations in `spec/` itself. Each function's doc comment names
//! the spec file, section and equation it implements; where the spec flags an erratum [E] or a
//! reconstruction [R], the corrected form is used and the comment says so.
//!
//! Files, one concept each:
//! - [`couette`]: circular Couette flow between rotating cylinders.
//! - [`drag_laws`]: single-sphere drag coefficients C_d(Re).
//! - [`settling`]: single-sphere terminal velocity and transient settling from rest.
//! - [`hindered_settling`]: Richardson–Zaki, Di Felice and the cloud settling velocities.
//! - [`hertz`]: Hertz normal impact, contact stiffness and damping ↔ restitution relations.
//! - [`restitution`]: Legendre wet restitution and the lubrication-only limit.
//! - [`oblique_impact`]: Walton's hard-sphere oblique impact model.
//! - [`spillage_model`]: the Euler-turbine analytical spillage model.
//! - [`spillage_calibration`]: its α and β fitted to simulated out-flowing fluxes (Tab. 8.1).
//! - [`erosion`]: erosion per impact (Arabnejad, Finnie, Oka, DNV, E/CRC).
//! - [`granular`]: the granular temperature and solids pressure of the wear model's KTGF.
//! - [`sliding_interface`]: conservative 1-D / periodic face-overlap mapping.
//! - [`channel_flows`]: Poiseuille/Couette channel, Taylor–Green vortex, hydrostatics.
//! - [`rotating_frame`]: the Coriolis tester's rotation (A39), a free particle seen from a
//!   rotating frame (A40), a sphere drifting out through fluid at rest in the frame, and the
//!   centrifugal pressure of fluid at rest in the frame.
//! - [`turbulent_channel`]: the log law of the wall and Dean's channel skin friction.
//! - helpers: [`roots`], [`ode`], [`special`], [`error`].

// Input checks are written `!(x > 0.0)` on purpose so that NaN is rejected too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod channel_flows;
pub mod couette;
pub mod drag_laws;
pub mod erosion;
pub mod error;
pub mod granular;
pub mod hertz;
pub mod hindered_settling;
pub mod oblique_impact;
pub mod ode;
pub mod restitution;
pub mod roots;
pub mod rotating_frame;
pub mod settling;
pub mod sliding_interface;
pub mod special;
pub mod spillage_calibration;
pub mod spillage_model;
pub mod turbulent_channel;

pub use error::{AnalyticError, Result};

/// Standard gravity used by the particle specs (particle-verification.md, "g = 9.81 m/s²").
pub const GRAVITY: f64 = 9.81;
