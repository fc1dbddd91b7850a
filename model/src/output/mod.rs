//! Output writers: ParaView (VTK XML), time series CSV, run summary JSON, PNG plots.

pub mod plot;
