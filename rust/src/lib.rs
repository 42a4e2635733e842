//! # slipstep-core
//!
//! Frictional contact of elastoplastic bodies in 2D (plane, axisymmetric) and 3D solved by the *adaptive incremental* procedure of
//! Abdalla, Ali-Eldin & Ghazy: no penalty parameter and no load steps. From the current state
//! the engine solves for the whole remaining load, computes the load scale at which the next
//! event happens (a gap closes, a pair separates, a stuck pair starts to slip, a slipping pair
//! sticks) and advances exactly to it. The result is an exact, piecewise-linear load path and
//! its event history.
//!
//! One module per concept, in the order of the paper:
//! - [`dim`]: the dimension as a type, chosen once by the front end: `Planar` (triangles, a
//!   stress state and a thickness) or `Spatial` (tetrahedra); the mesh, the model and the
//!   engine are generic over it, and what differs is its methods;
//! - [`material`]: the 3D law: elasticity D (eqs. 9, 18), von Mises plasticity (eq. 11);
//! - [`section`]: the stress state (plane strain, plane stress, axisymmetry, a solid) and a
//!   material bound to it;
//! - [`stress_integration`]: an element's stress along a strain increment (the elastic–plastic
//!   split of eq. 16, Prandtl–Reuss integrated with error control);
//! - [`element`]: element kinematics (the `Element` seam), the constant-strain triangle and
//!   the linear tetrahedron (eq. 10, K of eq. 36, P_σ of eq. 42), and which a dimension has
//!   (`Discretization`);
//! - [`mesh`]: meshes of a dimension (`Mesh<D>`), validation, bodies;
//! - [`contact`]: candidate pairs, their constraint vectors and statuses (eqs. 21–28, 41, 45–46);
//! - [`coulomb`]: Coulomb's law on a pair: capacity, the facets of the round cone, their
//!   turns, the stick → slip roots (eqs. 1–3, 41, 52–53);
//! - [`rigid_modes`]: rigid-body modes left free by the supports (3 per body in 2D, 6 in 3D);
//! - [`linalg`]: the equations and the sparse assembly; [`factor`]: the SPD factorization
//!   behind one seam (faer in-process, or PETSc's MUMPS over MPI ranks); [`low_rank`]: the
//!   factor plus a few rank-one terms (Woodbury), so that a yield needs no refactorization;
//! - [`events`]: scale factors of the next event (eqs. 48–57);
//! - [`driver`]: the incremental loop (§4), one module per phase (see its table);
//! - [`lcp`]: Lemke's method for the zero-length rate problem;
//! - [`model`]: input records and their validation; [`options`]: the solver options, declared
//!   once (key, default, range, meaning); [`records`]: output records;
//! - [`error`]: typed errors, one kind per failure; [`interrupt`]: stopping a run from outside
//!   in every phase.

pub mod contact;
pub mod coulomb;
pub mod dim;
pub mod driver;
pub mod element;
pub mod error;
pub mod events;
pub mod factor;
pub mod interrupt;
pub mod lcp;
pub mod linalg;
pub mod low_rank;
pub mod material;
pub mod mesh;
pub mod model;
pub mod options;
pub mod ordering;
pub mod records;
pub mod rigid_modes;
pub mod section;
pub mod stress_integration;

pub use driver::run;
pub use error::{Error, Result};
