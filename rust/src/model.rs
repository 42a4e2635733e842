//! What goes into the engine: a scene reduced to arrays, the names the messages use, the solver
//! options, and their validation (the core checks its own input, so every caller gets the same
//! checks). The output records live in `records` (re-exported here).

use crate::bail;
use crate::dim::Dim;
use crate::error::Result;
use crate::material::Material;
use crate::mesh::Mesh;
pub use crate::options::{Options, SnapshotRequest, DEFAULT_GROUP_TOL, DEFAULT_TANGENT_TURN};
pub use crate::records::*;

/// A candidate contact pair as given by the front end (see `contact::Pair`).
#[derive(Debug, Clone)]
pub struct PairInput {
    pub node_a: usize,
    pub node_b: Option<usize>,
    /// The target's unit normal (z = 0 in 2D).
    pub normal: [f64; 3],
    /// 3D: the pair's tangent basis (t1, t2), orthonormal with t1 × t2 = n; None: the
    /// engine's own (`contact::Frame::in_space`).
    pub tangents: Option<[[f64; 3]; 2]>,
    pub gap: f64,
    pub mu: f64,
    /// Index into `Names::contacts` of the case's contact this pair comes from.
    pub contact: usize,
    /// Node-to-segment (mortar-style) pairs: the weight c_i of every node in the constraint
    /// column (contactor > 0, target < 0, summing to 0). Empty: 1 at node_a, −1 at node_b.
    pub weights: Vec<(usize, f64)>,
}

/// Weights of a pair must cancel to this × their size (a rigid translation keeps the gap).
const WEIGHT_BALANCE: f64 = 1e-9;
/// The loads' nominal strain (`Model::nominal_strains`) at a stage's end must not exceed this:
/// beyond, the displacements exceed the scene's size, where small-strain contact (normals and
/// gaps fixed at the start) means nothing, and the gaps drown in the displacements' round-off
/// (at 1e20 the events could no longer be ordered; at 1e150 squares overflow f64).
const MAX_NOMINAL_STRAIN: f64 = 1.0;
/// A load reaching a nominal strain below this is no load to f64: its norms and products
/// (squares ~1e-200 of the scene's units and below) run into underflow.
const MIN_NOMINAL_STRAIN: f64 = 1e-100;

/// The case's names, so that messages say "body 'punch'" and "contact 'bottom'" instead of
/// indices. Empty vectors: bodies and contacts are named by number.
#[derive(Debug, Clone, Default)]
pub struct Names {
    pub bodies: Vec<String>,
    /// Body (index into `bodies`) of every element.
    pub element_body: Vec<usize>,
    pub contacts: Vec<String>,
    /// The named supports ([[bc]] that hold or prescribe DOFs) and the DOFs each holds, for the
    /// reactions recorded at every increment (`StepRecord::reaction`); a DOF counts in one.
    pub supports: Vec<(String, Vec<usize>)>,
}

/// A load pattern at factor 1: forces, prescribed displacements and rigid-obstacle motions
/// that a stage scales together (issue 13: named loads).
#[derive(Debug, Clone, Default)]
pub struct LoadPattern {
    pub name: String,
    /// Nodal forces (2 per node), or empty: none.
    pub force: Vec<f64>,
    /// Prescribed displacement components (DOF, value); these DOFs are eliminated like supports.
    pub displacement: Vec<(usize, f64)>,
    /// Rigid obstacle translations (index into `Names::contacts`, [dx, dy, dz]; dz = 0 in 2D).
    pub motion: Vec<(usize, [f64; 3])>,
}

/// One stage of the load path: the factor every pattern reaches at its end (`load` first, then
/// `Model::patterns`); factors start at 0 and are linear within a stage.
#[derive(Debug, Clone)]
pub struct Stage {
    pub name: String,
    pub factors: Vec<f64>,
}

/// A scene in the plane (`Planar`) or in space (`Spatial`): the dimension is its type, read
/// once by the front end.
#[derive(Debug, Clone)]
pub struct Model<D: Dim> {
    /// Triangles or tetrahedra.
    pub mesh: Mesh<D>,
    pub element_material: Vec<usize>,
    pub materials: Vec<Material>,
    /// What only the plane has: the stress state and the out-of-plane thickness
    /// (`dim::PlaneSection`); nothing in space.
    pub section: D::Section,
    /// DOFs with u = 0 (dim·node + component).
    pub fixed_dofs: Vec<usize>,
    /// The force of the pattern named `load` at factor 1 (length dim·nodes).
    pub load: Vec<f64>,
    /// Further load patterns (forces, prescribed displacements, obstacle motions).
    pub patterns: Vec<LoadPattern>,
    /// The load path; empty: one stage with every pattern at factor 1.
    pub stages: Vec<Stage>,
    pub pairs: Vec<PairInput>,
    pub names: Names,
    pub options: Options,
}

impl<D: Dim> Model<D> {
    /// Whether any material can yield (a plastic run: no reduced elastic space, drift
    /// corrections are not round-off).
    pub fn has_plastic_material(&self) -> bool {
        self.materials.iter().any(|m| m.is_plastic())
    }

    /// Every check the engine needs before it assembles anything: mesh, materials, loads,
    /// supports, contact pairs, names and options. Errors name the place and the fix.
    pub fn validate(&self) -> Result<()> {
        self.mesh.validate()?;
        self.options.validate()?;
        self.validate_bulk()?;
        self.validate_names()?;
        self.validate_path()?;
        self.validate_magnitudes()?;
        let length_scale = self.mesh.diameter();
        let (body_of_node, _) = self.mesh.bodies();
        let mut seen = std::collections::HashSet::new();
        for (k, p) in self.pairs.iter().enumerate() {
            self.validate_pair(k, p, &body_of_node, length_scale)?;
            if !seen.insert((p.node_a, p.node_b)) {
                bail!(Input, "{} repeats the pair of node {} (a node may face one target once): remove the duplicate", self.pair_name(k), p.node_a);
            }
        }
        Ok(())
    }

    /// The DOFs held at u = 0: `fixed_dofs`, and in axisymmetry u_r of every node on the axis
    /// r = 0 (a ring of zero radius cannot move radially), added here so every caller gets it.
    pub fn supported_dofs(&self) -> Vec<usize> {
        let mut dofs = self.fixed_dofs.clone();
        if self.is_axisymmetric() {
            dofs.extend(self.mesh.axis_nodes().iter().map(|&i| D::N * i));
        }
        dofs
    }

    /// DOFs per node: 2 in the plane, 3 in space.
    pub fn dim(&self) -> usize {
        D::N
    }

    /// A model of rings about the axis.
    pub fn is_axisymmetric(&self) -> bool {
        D::is_axisymmetric(&self.section)
    }

    /// "node i (x)" of DOF d.
    pub fn dof_name(&self, d: usize) -> String {
        format!("node {} ({})", d / self.dim(), ["x", "y", "z"][d % self.dim()])
    }

    /// The out-of-plane extent forces scale with: the thickness t in plane strain and plane
    /// stress, the largest circumference 2π r_max in axisymmetry (forces are ring totals), the
    /// mesh's diameter in 3D (a force over E × a length² is a strain).
    pub fn depth(&self) -> f64 {
        if self.is_axisymmetric() {
            let r_max = self.mesh.nodes.iter().fold(0.0f64, |m, p| m.max(p.as_ref()[0]));
            return 2.0 * std::f64::consts::PI * r_max;
        }
        D::thickness(&self.section).unwrap_or_else(|| self.mesh.diameter())
    }

    fn validate_bulk(&self) -> Result<()> {
        let n_dofs = self.dim() * self.mesh.n_nodes();
        if self.is_axisymmetric() {
            if let Some((e, i)) = self.mesh.element_left_of_axis() {
                let body = self
                    .names
                    .element_body
                    .get(e)
                    .and_then(|&b| self.names.bodies.get(b))
                    .map(|b| format!(" of body '{b}'"))
                    .unwrap_or_default();
                bail!(Input, "element {e}{body} has node {i} at r = x = {:.6} < 0: an axisymmetric mesh lies in x = r >= 0 (the axis is x = 0); move the body to x >= 0", self.mesh.nodes[i].as_ref()[0]);
            }
        } else if let Some(t) = D::thickness(&self.section) {
            if !(t.is_finite() && t > 0.0) {
                bail!(
                    Input,
                    "thickness = {t} is not allowed: give a positive out-of-plane thickness"
                );
            }
        }
        if self.materials.is_empty() {
            bail!(Input, "no material given: every body needs a material with E and nu");
        }
        for (i, m) in self.materials.iter().enumerate() {
            m.validate(&self.material_name(i))?;
        }
        if self.element_material.len() != self.mesh.n_elements() {
            bail!(
                Input,
                "element_material has {} entries for {} elements",
                self.element_material.len(),
                self.mesh.n_elements()
            );
        }
        if let Some((e, &m)) =
            self.element_material.iter().enumerate().find(|(_, &m)| m >= self.materials.len())
        {
            bail!(
                Input,
                "element {e} uses material {m}, but only {} materials are given",
                self.materials.len()
            );
        }
        if self.load.len() != n_dofs {
            bail!(
                Input,
                "the load vector has {} entries for {} DOFs ({} per node)",
                self.load.len(),
                n_dofs,
                self.dim()
            );
        }
        if let Some(d) = self.load.iter().position(|v| !v.is_finite()) {
            bail!(
                Input,
                "the load at {} is not finite: check the pressure/traction values",
                self.dof_name(d)
            );
        }
        if let Some(&d) = self.fixed_dofs.iter().find(|&&d| d >= n_dofs) {
            bail!(Input, "fixed DOF {d} is out of range (the mesh has {n_dofs} DOFs)");
        }
        Ok(())
    }

    /// Patterns (finite, in range, prescribed DOFs not also fixed or repeated, motions on rigid
    /// contacts only) and stages (one factor per pattern, finite, each stage changes something).
    fn validate_path(&self) -> Result<()> {
        let n_dofs = self.dim() * self.mesh.n_nodes();
        let mut prescribed = vec![false; n_dofs];
        self.supported_dofs().iter().filter(|&&d| d < n_dofs).for_each(|&d| prescribed[d] = true);
        for pat in &self.patterns {
            let name = &pat.name;
            if !pat.force.is_empty() && pat.force.len() != n_dofs {
                bail!(
                    Input,
                    "load '{name}': the force vector has {} entries for {n_dofs} DOFs",
                    pat.force.len()
                );
            }
            if pat.force.iter().any(|v| !v.is_finite()) {
                bail!(
                    Input,
                    "load '{name}': a force is not finite: check its pressure/traction values"
                );
            }
            for &(d, v) in &pat.displacement {
                if d >= n_dofs || !v.is_finite() {
                    bail!(Input, "load '{name}': prescribed DOF {d} is out of range or its value {v} is not finite");
                }
                if std::mem::replace(&mut prescribed[d], true) {
                    bail!(Input, "load '{name}': {} is already held by a support or another prescribed displacement: prescribe each component once", self.dof_name(d));
                }
            }
            for &(c, m) in &pat.motion {
                if !m.iter().all(|v| v.is_finite()) {
                    bail!(Input, "load '{name}': the motion of contact {c} is not finite");
                }
                if let Some(k) =
                    self.pairs.iter().position(|p| p.contact == c && p.node_b.is_some())
                {
                    bail!(Input, "load '{name}': motion on {}, a pair of deformable bodies: motion moves a rigid obstacle; prescribe a displacement on one of the bodies instead", self.pair_name(k));
                }
            }
        }
        let n_factors = 1 + self.patterns.len();
        let mut previous = vec![0.0; n_factors];
        for (k, stage) in self.stages.iter().enumerate() {
            let name = self.stage_label(k);
            if stage.factors.len() != n_factors {
                bail!(
                    Input,
                    "{name} has {} factors for {n_factors} load patterns (load first)",
                    stage.factors.len()
                );
            }
            if stage.factors.iter().any(|v| !v.is_finite()) {
                bail!(Input, "{name}: a load factor is not finite");
            }
            if stage.factors == previous {
                bail!(
                    Input,
                    "{name} changes no load factor: remove it, or give the factors it should reach"
                );
            }
            previous = stage.factors.clone();
        }
        self.options.validate_times(self.stages.len().max(1))
    }

    /// Every stage's end within small strain and f64's range: the loads' nominal strains,
    /// times the factors they reach there, add up to at most `MAX_NOMINAL_STRAIN`, and each
    /// nonzero one is at least `MIN_NOMINAL_STRAIN` (factors are linear within a stage, so its
    /// ends bound it). Names the stage, the load, its factor, and the factor allowed.
    fn validate_magnitudes(&self) -> Result<()> {
        let strains = self.nominal_strains();
        let one_stage = [Stage { name: String::new(), factors: vec![1.0; strains.len()] }];
        let stages = if self.stages.is_empty() { &one_stage[..] } else { &self.stages[..] };
        for (k, stage) in stages.iter().enumerate() {
            let reached: Vec<f64> =
                stage.factors.iter().zip(&strains).map(|(f, (_, e))| f.abs() * e).collect();
            let total: f64 = reached.iter().sum();
            let p = (0..reached.len())
                .fold(0, |best, p| if reached[p] > reached[best] { p } else { best });
            let tiny = reached.iter().position(|&e| e > 0.0 && e < MIN_NOMINAL_STRAIN);
            let (p, bound, hint) = match (total > MAX_NOMINAL_STRAIN, tiny) {
                (true, _) => (
                    p,
                    "at most 1 is meaningful (small strain: displacements up to the scene's size)",
                    MAX_NOMINAL_STRAIN / total,
                ),
                (false, Some(p)) => (
                    p,
                    "at least 1e-100 is needed (smaller loads underflow f64's products)",
                    MIN_NOMINAL_STRAIN / reached[p],
                ),
                (false, None) => continue,
            };
            let (name, factor, lower) = (&strains[p].0, stage.factors[p], hint < 1.0);
            let (at, fix) = match self.stages.is_empty() {
                true if lower => (
                    format!("load '{name}'"),
                    format!("lower its values at least {:.1e}-fold", 1.0 / hint),
                ),
                true => (
                    format!("load '{name}'"),
                    format!("raise its values at least {hint:.1e}-fold, or remove it"),
                ),
                false if lower => (
                    format!("{}: load '{name}' at factor {factor:e}", self.stage_label(k)),
                    format!("keep |factor| <= {:.3e} at these values", factor.abs() * hint),
                ),
                false => (
                    format!("{}: load '{name}' at factor {factor:e}", self.stage_label(k)),
                    format!("keep |factor| >= {:.3e} at these values, or 0", factor.abs() * hint),
                ),
            };
            bail!(Input, "{at} reaches a nominal strain of {:.1e} (displacement or motion over the scene's size, force over E × its section); {bound}: {fix}", reached[p]);
        }
        Ok(())
    }

    /// Each load's nominal strain at factor 1 (`load` first, then the patterns): its force
    /// Σ|F| over the smallest E × the section depth × L, its largest prescribed displacement or
    /// obstacle motion over L; L the mesh's diameter plus its largest initial gap.
    fn nominal_strains(&self) -> Vec<(String, f64)> {
        let length = self.mesh.diameter() + self.pairs.iter().fold(0.0f64, |g, p| g.max(p.gap));
        let stiffness = self.materials.iter().fold(f64::INFINITY, |e, m| e.min(m.young))
            * self.depth()
            * length;
        let force = |f: &[f64]| f.iter().map(|v| v.abs() / stiffness).sum::<f64>();
        let mut strains = vec![(String::from("load"), force(&self.load))];
        for pat in &self.patterns {
            let moved = pat
                .displacement
                .iter()
                .map(|d| d.1)
                .chain(pat.motion.iter().flat_map(|m| m.1))
                .fold(0.0f64, |a, v| a.max(v.abs() / length));
            strains.push((pat.name.clone(), force(&pat.force).max(moved)));
        }
        strains
    }

    fn validate_names(&self) -> Result<()> {
        let n = &self.names;
        if !n.element_body.is_empty() && n.element_body.len() != self.mesh.n_elements() {
            bail!(
                Input,
                "names.element_body has {} entries for {} elements",
                n.element_body.len(),
                self.mesh.n_elements()
            );
        }
        if let Some(&b) = n.element_body.iter().find(|&&b| b >= n.bodies.len()) {
            bail!(
                Input,
                "names.element_body refers to body {b}, but only {} body names are given",
                n.bodies.len()
            );
        }
        let n_dofs = self.dim() * self.mesh.n_nodes();
        if let Some((name, &d)) = n
            .supports
            .iter()
            .find_map(|(name, dofs)| dofs.iter().find(|&&d| d >= n_dofs).map(|d| (name, d)))
        {
            bail!(Input, "support '{name}' names DOF {d}, but the mesh has {n_dofs} DOFs");
        }
        if !n.contacts.is_empty() {
            if let Some((k, p)) =
                self.pairs.iter().enumerate().find(|(_, p)| p.contact >= n.contacts.len())
            {
                bail!(
                    Input,
                    "pair {k} refers to contact {}, but only {} contact names are given",
                    p.contact,
                    n.contacts.len()
                );
            }
        }
        Ok(())
    }

    fn validate_pair(
        &self,
        k: usize,
        p: &PairInput,
        body_of_node: &[usize],
        length_scale: f64,
    ) -> Result<()> {
        let name = self.pair_name(k);
        let in_mesh = |i: usize| i < self.mesh.n_nodes() && body_of_node[i] != usize::MAX;
        if !in_mesh(p.node_a) || p.node_b.map_or(false, |b| !in_mesh(b)) {
            let target = p.node_b.map_or(String::from("a rigid line"), |b| format!("node {b}"));
            bail!(Input, "{name} (node {} against {target}) refers to a node of no element: check the contact surface tags", p.node_a);
        }
        if p.node_b == Some(p.node_a) {
            bail!(Input, "{name} joins node {} to itself", p.node_a);
        }
        if !(p.mu.is_finite() && p.mu >= 0.0) {
            bail!(
                Input,
                "{name}: mu = {} is not allowed: the friction coefficient must be >= 0",
                p.mu
            );
        }
        if let Some(&(i, c)) = p.weights.iter().find(|&&(i, c)| !in_mesh(i) || !c.is_finite()) {
            bail!(Input, "{name}: weight {c} on node {i} is not allowed: node-to-segment weights need finite values on nodes of an element");
        }
        let (sum, size) = p.weights.iter().fold((0.0, 0.0), |(s, a), &(_, c)| (s + c, a + c.abs()));
        if sum.abs() > WEIGHT_BALANCE * size {
            bail!(Input, "{name}: its node weights sum to {sum:.3e}, not 0: the contactor weights must sum to 1 and the target weights to -1");
        }
        let nn = (p.normal[0].powi(2) + p.normal[1].powi(2) + p.normal[2].powi(2)).sqrt();
        if !nn.is_finite() || (nn - 1.0).abs() > 1e-6 {
            bail!(Input, "{name}: the normal {:?} is not a unit vector", &p.normal[..self.dim()]);
        }
        if !p.gap.is_finite() {
            bail!(Input, "{name}: the initial gap is not finite");
        }
        if p.gap < -1e-9 * length_scale {
            bail!(Input, "initial penetration at {name} (node {}): gap {:.3e} < 0; move the bodies apart so that they at most touch", p.node_a, p.gap);
        }
        Ok(())
    }

    /// "stage 'NAME'" of stage k (0-based), or "stage k+1" when it has no name.
    pub fn stage_label(&self, k: usize) -> String {
        match self.stages.get(k).filter(|s| !s.name.is_empty()) {
            Some(s) => format!("stage '{}'", s.name),
            None => format!("stage {}", k + 1),
        }
    }

    /// "contact 'NAME' pair k (node n at (x, y))", or "contact pair k (node n)" without names.
    pub fn pair_name(&self, k: usize) -> String {
        let p = &self.pairs[k];
        let at = self.mesh.nodes.get(p.node_a).map_or_else(String::new, |x| {
            let coordinates: Vec<String> = x.as_ref().iter().map(|v| format!("{v:.6}")).collect();
            format!(" at ({})", coordinates.join(", "))
        });
        match self.names.contacts.get(p.contact) {
            Some(c) => format!("contact '{c}' pair {k} (node {}{at})", p.node_a),
            None => format!("contact pair {k} (node {}{at})", p.node_a),
        }
    }

    /// "body 'NAME' material" of the first element that uses material i, or "material i".
    pub fn material_name(&self, i: usize) -> String {
        let body = self
            .element_material
            .iter()
            .position(|&m| m == i)
            .and_then(|e| self.names.element_body.get(e))
            .and_then(|&b| self.names.bodies.get(b));
        body.map_or_else(|| format!("material {i}"), |b| format!("body '{b}' material"))
    }

    /// "body 'NAME'" of a connected component of the mesh (named by its first element).
    pub fn body_name(&self, first_element: usize) -> String {
        match self.names.element_body.get(first_element).and_then(|&b| self.names.bodies.get(b)) {
            Some(b) => format!("body '{b}'"),
            None => format!("the body of element {first_element}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snapshot_times_lie_on_the_path() {
        for (times, n_stages) in
            [(vec![0.5, f64::NAN], 1), (vec![0.0], 1), (vec![1.5], 1), (vec![2.5], 2)]
        {
            let o = Options { snapshots: SnapshotRequest::Times(times), ..Options::default() };
            let err = o.validate_times(n_stages).unwrap_err().message;
            assert!(err.starts_with("options.times") && err.contains("is not allowed"), "{err}");
        }
        let o = Options { snapshots: SnapshotRequest::Times(vec![0.5, 2.0]), ..Options::default() };
        assert!(o.validate_times(2).is_ok());
    }
}
