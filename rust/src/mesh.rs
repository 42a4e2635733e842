//! Meshes of triangles (the plane) or tetrahedra (space), typed by their dimension (`dim`):
//! validation and the split into bodies (connected components).

use crate::dim::{signed_area2, signed_volume6, Dim, Planar, Spatial};
use crate::error::Result;

/// In axisymmetry a node within this × the mesh diameter of x = 0 lies on the axis (round-off
/// of the node coordinates); one further left is at r < 0.
pub const AXIS_TOLERANCE: f64 = 1e-9;

/// A mesh of dimension `D`: its nodes and its elements (triangles in the plane, tetrahedra in
/// space).
#[derive(Debug, Clone)]
pub struct Mesh<D: Dim> {
    /// Node coordinates.
    pub nodes: Vec<D::Point>,
    /// The elements' nodes: triangles counter-clockwise, tetrahedra positively oriented.
    pub elements: Vec<D::Cell>,
}

impl<D: Dim> Mesh<D> {
    pub fn new(nodes: Vec<D::Point>, elements: Vec<D::Cell>) -> Self {
        Mesh { nodes, elements }
    }

    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }

    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }

    /// The nodes of element `e`.
    pub fn element_nodes(&self, e: usize) -> &[usize] {
        self.elements[e].as_ref()
    }

    /// The coordinates of node i (z = 0 in the plane).
    pub fn point(&self, i: usize) -> [f64; 3] {
        D::coordinates(&self.nodes[i])
    }

    /// Length of the diagonal of the bounding box: the length scale of tolerances.
    pub fn diameter(&self) -> f64 {
        let (lo, hi) = self.nodes.iter().fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), p| {
            let p = p.as_ref();
            (
                std::array::from_fn(|k| if k < D::N { lo[k].min(p[k]) } else { lo[k] }),
                std::array::from_fn(|k| if k < D::N { hi[k].max(p[k]) } else { hi[k] }),
            )
        });
        (0..D::N).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
    }

    /// The nodes used by an element that lie on the axis x = 0 (within `AXIS_TOLERANCE`).
    pub fn axis_nodes(&self) -> Vec<usize> {
        let tol = AXIS_TOLERANCE * self.diameter();
        let mut on_axis = vec![false; self.nodes.len()];
        self.elements
            .iter()
            .flat_map(|t| t.as_ref())
            .filter(|&&i| self.nodes[i].as_ref()[0].abs() <= tol)
            .for_each(|&i| on_axis[i] = true);
        (0..self.nodes.len()).filter(|&i| on_axis[i]).collect()
    }

    /// The first element with a node at r = x < 0 (beyond `AXIS_TOLERANCE`): (element, node).
    pub fn element_left_of_axis(&self) -> Option<(usize, usize)> {
        let tol = AXIS_TOLERANCE * self.diameter();
        let x = |i: usize| self.nodes[i].as_ref()[0];
        self.elements
            .iter()
            .enumerate()
            .find_map(|(e, t)| t.as_ref().iter().find(|&&i| x(i) < -tol).map(|&i| (e, i)))
    }

    /// Reject meshes the element routines cannot integrate: no elements, NaN/inf coordinates,
    /// node ids out of range, repeated nodes in an element, inverted or degenerate elements.
    pub fn validate(&self) -> Result<()> {
        D::validate_cells(&self.nodes, &self.elements)
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

/// The plane's meshes: triangles.
impl Mesh<Planar> {
    /// Twice the signed area of element `e` (> 0 when counter-clockwise).
    pub fn signed_area2(&self, e: usize) -> f64 {
        signed_area2(self.elements[e].map(|i| self.nodes[i]))
    }
}

/// Meshes in space: tetrahedra.
impl Mesh<Spatial> {
    /// det[x1 − x0, x2 − x0, x3 − x0] of tetrahedron `e` (6 × its signed volume).
    pub fn signed_volume6(&self, e: usize) -> f64 {
        signed_volume6(self.elements[e].map(|i| self.nodes[i]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Mesh<Planar> {
        Mesh::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], vec![[0, 1, 2], [0, 2, 3]])
    }

    #[test]
    fn inverted_triangle_is_named() {
        let mut m = square();
        m.elements[1] = [0, 3, 2];
        let err = m.validate().unwrap_err().message;
        assert!(err.starts_with("element 1 is inverted"), "{err}");
    }

    #[test]
    fn degenerate_triangle_is_named() {
        let mut m = square();
        m.nodes.push([2.0, 0.0]);
        m.elements.push([0, 1, 4]);
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
        m.elements.push([off, off + 1, off + 2]);
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
pub fn test_grid(nx: usize, ny: usize, dx: f64, dy: f64) -> Mesh<Planar> {
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
    Mesh::new(nodes, triangles)
}
