//! Meshes of triangles (2D) or tetrahedra (3D): validation and the split into bodies
//! (connected components).

use crate::bail;
use crate::error::Result;

/// In axisymmetry a node within this × the mesh diameter of x = 0 lies on the axis (round-off
/// of the node coordinates); one further left is at r < 0.
pub const AXIS_TOLERANCE: f64 = 1e-9;

/// A flat or inverted tetrahedron: |det[x1 − x0, x2 − x0, x3 − x0]| at most this × the cube of
/// its longest edge (the triangles' 1e-10 of the squared longest side, one dimension up).
const FLAT_TETRAHEDRON: f64 = 1e-10;

/// A mesh of one dimension: `nodes` and `triangles` (2D), or `points` and `tetrahedra` (3D);
/// the other pair is empty.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Node coordinates (x, y) of a 2D mesh.
    pub nodes: Vec<[f64; 2]>,
    /// CST connectivity, counter-clockwise.
    pub triangles: Vec<[usize; 3]>,
    /// Node coordinates (x, y, z) of a 3D mesh.
    pub points: Vec<[f64; 3]>,
    /// Linear tetrahedra, positively oriented.
    pub tetrahedra: Vec<[usize; 4]>,
}

impl Mesh {
    /// A 2D mesh.
    pub fn plane(nodes: Vec<[f64; 2]>, triangles: Vec<[usize; 3]>) -> Self {
        Mesh { nodes, triangles, ..Default::default() }
    }

    /// A 3D mesh.
    pub fn space(points: Vec<[f64; 3]>, tetrahedra: Vec<[usize; 4]>) -> Self {
        Mesh { points, tetrahedra, ..Default::default() }
    }

    /// 3 for a mesh of tetrahedra, else 2: the DOFs per node.
    pub fn dim(&self) -> usize {
        if self.points.is_empty() {
            2
        } else {
            3
        }
    }

    pub fn n_nodes(&self) -> usize {
        self.nodes.len().max(self.points.len())
    }

    pub fn n_elements(&self) -> usize {
        self.triangles.len().max(self.tetrahedra.len())
    }

    /// The nodes of element `e`.
    pub fn element_nodes(&self, e: usize) -> &[usize] {
        match self.dim() {
            2 => &self.triangles[e],
            _ => &self.tetrahedra[e],
        }
    }

    /// The coordinates of node i (z = 0 in 2D).
    pub fn point(&self, i: usize) -> [f64; 3] {
        match self.dim() {
            2 => [self.nodes[i][0], self.nodes[i][1], 0.0],
            _ => self.points[i],
        }
    }

    /// det[x1 − x0, x2 − x0, x3 − x0] of tetrahedron `e` (6 × its signed volume).
    pub fn signed_volume6(&self, e: usize) -> f64 {
        let p = self.tetrahedra[e].map(|i| self.points[i]);
        let d = |k: usize| [p[k][0] - p[0][0], p[k][1] - p[0][1], p[k][2] - p[0][2]];
        let (a, b, c) = (d(1), d(2), d(3));
        a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0])
    }

    /// Twice the signed area of element `e` (> 0 when counter-clockwise).
    pub fn signed_area2(&self, e: usize) -> f64 {
        let [a, b, c] = self.triangles[e];
        let (pa, pb, pc) = (self.nodes[a], self.nodes[b], self.nodes[c]);
        (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pc[0] - pa[0]) * (pb[1] - pa[1])
    }

    /// Length of the diagonal of the bounding box: the length scale of tolerances.
    pub fn diameter(&self) -> f64 {
        if self.dim() == 3 {
            let (lo, hi) =
                self.points.iter().fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), p| {
                    (
                        std::array::from_fn(|k| lo[k].min(p[k])),
                        std::array::from_fn(|k| hi[k].max(p[k])),
                    )
                });
            return (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
        }
        let (xmin, xmax, ymin, ymax) =
            self.nodes.iter().fold((f64::MAX, f64::MIN, f64::MAX, f64::MIN), |b, p| {
                (b.0.min(p[0]), b.1.max(p[0]), b.2.min(p[1]), b.3.max(p[1]))
            });
        ((xmax - xmin).powi(2) + (ymax - ymin).powi(2)).sqrt()
    }

    /// The nodes used by an element that lie on the axis x = 0 (within `AXIS_TOLERANCE`).
    pub fn axis_nodes(&self) -> Vec<usize> {
        let tol = AXIS_TOLERANCE * self.diameter();
        let mut on_axis = vec![false; self.nodes.len()];
        self.triangles
            .iter()
            .flatten()
            .filter(|&&i| self.nodes[i][0].abs() <= tol)
            .for_each(|&i| on_axis[i] = true);
        (0..self.nodes.len()).filter(|&i| on_axis[i]).collect()
    }

    /// The first element with a node at r = x < 0 (beyond `AXIS_TOLERANCE`): (element, node).
    pub fn element_left_of_axis(&self) -> Option<(usize, usize)> {
        let tol = AXIS_TOLERANCE * self.diameter();
        self.triangles
            .iter()
            .enumerate()
            .find_map(|(e, t)| t.iter().find(|&&i| self.nodes[i][0] < -tol).map(|&i| (e, i)))
    }

    /// Reject meshes the element routines cannot integrate: no elements, NaN/inf coordinates,
    /// node ids out of range, repeated nodes in a triangle, inverted or degenerate triangles.
    pub fn validate(&self) -> Result<()> {
        if self.dim() == 3 {
            return self.validate_space();
        }
        if self.triangles.is_empty() {
            bail!(
                Input,
                "the mesh has no triangles: give each body a mesh with at least one element"
            );
        }
        for (i, p) in self.nodes.iter().enumerate() {
            if !p[0].is_finite() || !p[1].is_finite() {
                bail!(
                    Input,
                    "node {i} has a non-finite coordinate ({}, {}): fix the mesh file",
                    p[0],
                    p[1]
                );
            }
        }
        let n = self.nodes.len();
        for (e, t) in self.triangles.iter().enumerate() {
            if let Some(&bad) = t.iter().find(|&&v| v >= n) {
                bail!(Input, "element {e} refers to node {bad}, but the mesh has only {n} nodes: fix the connectivity");
            }
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                bail!(
                    Input,
                    "element {e} repeats a node ({:?}): remove the degenerate triangle",
                    t
                );
            }
        }
        for e in 0..self.triangles.len() {
            let a2 = self.signed_area2(e);
            let [a, b, c] = self.triangles[e];
            let longest2 = [(a, b), (b, c), (c, a)]
                .iter()
                .map(|&(i, j)| {
                    let (p, q) = (self.nodes[i], self.nodes[j]);
                    (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)
                })
                .fold(0.0, f64::max);
            // Degenerate: height below 1e-10 of the longest side (zero area or collinear nodes).
            if a2.abs() <= 1e-10 * longest2 {
                bail!(Input, "element {e} is degenerate (area {:.3e} for a longest side of {:.3e}): remove it or move its nodes apart", a2 / 2.0, longest2.sqrt());
            }
            if a2 < 0.0 {
                bail!(Input, "element {e} is inverted (signed area {:.3e}): list its nodes counter-clockwise", a2 / 2.0);
            }
        }
        Ok(())
    }

    /// `validate` of a mesh of tetrahedra: finite coordinates, node ids in range, four distinct
    /// nodes, positive volume (an inverted or flat tetrahedron is named by its index).
    fn validate_space(&self) -> Result<()> {
        if self.tetrahedra.is_empty() {
            bail!(Input, "the mesh has no tetrahedra: give each body a volume mesh with at least one element");
        }
        if let Some((i, p)) =
            self.points.iter().enumerate().find(|(_, p)| p.iter().any(|v| !v.is_finite()))
        {
            bail!(
                Input,
                "node {i} has a non-finite coordinate ({}, {}, {}): fix the mesh file",
                p[0],
                p[1],
                p[2]
            );
        }
        let n = self.points.len();
        for (e, t) in self.tetrahedra.iter().enumerate() {
            if let Some(&bad) = t.iter().find(|&&v| v >= n) {
                bail!(Input, "element {e} refers to node {bad}, but the mesh has only {n} nodes: fix the connectivity");
            }
            if (0..4).any(|k| t[k + 1..].contains(&t[k])) {
                bail!(
                    Input,
                    "element {e} repeats a node ({t:?}): remove the degenerate tetrahedron"
                );
            }
            let det = self.signed_volume6(e);
            let longest = (0..4)
                .flat_map(|a| (a + 1..4).map(move |b| (a, b)))
                .map(|(a, b)| {
                    let (p, q) = (self.points[t[a]], self.points[t[b]]);
                    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
                })
                .fold(0.0, f64::max);
            if det.abs() <= FLAT_TETRAHEDRON * longest.powi(3) {
                bail!(Input, "element {e} is a flat tetrahedron (volume {:.3e} for a longest edge of {longest:.3e}): remove it or move its nodes apart", det / 6.0);
            }
            if det < 0.0 {
                bail!(Input, "element {e} is an inverted tetrahedron (signed volume {:.3e}): list its nodes so that det[x1 - x0, x2 - x0, x3 - x0] > 0", det / 6.0);
            }
        }
        Ok(())
    }

    /// Body index of every node (connected components of the element graph); nodes used by
    /// no element get `usize::MAX`. Returns (body_of_node, number_of_bodies).
    pub fn bodies(&self) -> (Vec<usize>, usize) {
        let n = self.n_nodes();
        let mut parent: Vec<usize> = (0..n).collect();
        fn find(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        let mut used = vec![false; n];
        for t in (0..self.n_elements()).map(|e| self.element_nodes(e)) {
            for &v in t {
                used[v] = true;
            }
            for k in 1..t.len() {
                let (ra, rb) = (find(&mut parent, t[0]), find(&mut parent, t[k]));
                if ra != rb {
                    parent[ra.max(rb)] = ra.min(rb);
                }
            }
        }
        let mut body_of_root = vec![usize::MAX; n];
        let mut body = vec![usize::MAX; n];
        let mut count = 0;
        for i in 0..n {
            if !used[i] {
                continue;
            }
            let r = find(&mut parent, i);
            if body_of_root[r] == usize::MAX {
                body_of_root[r] = count;
                count += 1;
            }
            body[i] = body_of_root[r];
        }
        (body, count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Mesh {
        Mesh::plane(
            vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    #[test]
    fn inverted_triangle_is_named() {
        let mut m = square();
        m.triangles[1] = [0, 3, 2];
        let err = m.validate().unwrap_err().message;
        assert!(err.starts_with("element 1 is inverted"), "{err}");
    }

    #[test]
    fn degenerate_triangle_is_named() {
        let mut m = square();
        m.nodes.push([2.0, 0.0]);
        m.triangles.push([0, 1, 4]);
        let err = m.validate().unwrap_err().message;
        assert!(err.starts_with("element 2 is degenerate"), "{err}");
    }

    #[test]
    fn nan_node_is_named() {
        let mut m = square();
        m.nodes[3][1] = f64::NAN;
        assert!(m.validate().unwrap_err().message.starts_with("node 3 has a non-finite"));
    }

    #[test]
    fn two_bodies_are_found() {
        let mut m = square();
        let off = m.nodes.len();
        for p in square().nodes {
            m.nodes.push([p[0] + 3.0, p[1]]);
        }
        m.triangles.push([off, off + 1, off + 2]);
        let (body, n) = m.bodies();
        assert_eq!(n, 2);
        assert_eq!(body[0], 0);
        assert_eq!(body[off], 1);
        assert_eq!(body[off + 3], usize::MAX); // unused node
    }

    #[test]
    fn axis_nodes_and_nodes_left_of_the_axis() {
        let mut m = square();
        m.nodes[3][0] = -1e-12; // round-off: on the axis
        assert_eq!(m.axis_nodes(), vec![0, 3]);
        assert_eq!(m.element_left_of_axis(), None);
        m.nodes[3][0] = -1e-3;
        assert_eq!(m.element_left_of_axis(), Some((1, 3)));
    }
}

/// Tests: a structured grid of nx × ny nodes spaced dx, dy, each cell cut into two triangles.
#[cfg(test)]
pub fn test_grid(nx: usize, ny: usize, dx: f64, dy: f64) -> Mesh {
    let nodes: Vec<[f64; 2]> =
        (0..ny).flat_map(|j| (0..nx).map(move |i| [i as f64 * dx, j as f64 * dy])).collect();
    let mut triangles = vec![];
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let a = nx * j + i;
            triangles.push([a, a + 1, a + nx + 1]);
            triangles.push([a, a + nx + 1, a + nx]);
        }
    }
    Mesh::plane(nodes, triangles)
}
