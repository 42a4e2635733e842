//! TEMPORARY stub until the Lemke module lands.
use nalgebra::{DMatrix, DVector};
#[derive(Debug, Clone, PartialEq)]
pub enum LcpFailure { Ray { pivots: usize }, PivotLimit { pivots: usize }, BadInput }
pub struct LcpSolution { pub z: DVector<f64>, pub w: DVector<f64>, pub pivots: usize }
pub fn lemke(_m: &DMatrix<f64>, _q: &DVector<f64>, _max_pivots: usize) -> Result<LcpSolution, LcpFailure> { Err(LcpFailure::BadInput) }
