//! Whole-engine tests on small structured meshes: patch tests, flat contact, rigid-body
//! freedom. (Hertz, Spence and the event history on graded meshes are tested from Python.)

use slipstep_core::dim::{Planar, PlaneSection};
use slipstep_core::material::{Material, Plane};
use slipstep_core::mesh::Mesh;
use slipstep_core::model::*;

/// nx × ny rectangle [x0, x0+w] × [y0, y0+h], two triangles per cell.
fn rectangle(x0: f64, y0: f64, w: f64, h: f64, nx: usize, ny: usize) -> Mesh<Planar> {
    let mut nodes = vec![];
    for j in 0..=ny {
        for i in 0..=nx {
            nodes.push([x0 + w * i as f64 / nx as f64, y0 + h * j as f64 / ny as f64]);
        }
    }
    let mut triangles = vec![];
    for j in 0..ny {
        for i in 0..nx {
            let a = j * (nx + 1) + i;
            let (b, c, d) = (a + 1, a + nx + 2, a + nx + 1);
            if (i + j) % 2 == 0 {
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            } else {
                triangles.push([a, b, d]);
                triangles.push([b, c, d]);
            }
        }
    }
    Mesh::<Planar>::new(nodes, triangles)
}

fn nodes_where(mesh: &Mesh<Planar>, f: impl Fn([f64; 2]) -> bool) -> Vec<usize> {
    (0..mesh.nodes.len()).filter(|&i| f(mesh.nodes[i])).collect()
}

/// Consistent nodal loads of a uniform traction on the edge y = y_top (nodes sorted by x).
fn top_traction(mesh: &Mesh<Planar>, y_top: f64, traction: [f64; 2], load: &mut [f64]) {
    let mut top = nodes_where(mesh, |p| (p[1] - y_top).abs() < 1e-12);
    top.sort_by(|&a, &b| mesh.nodes[a][0].partial_cmp(&mesh.nodes[b][0]).unwrap());
    for w in top.windows(2) {
        let len = mesh.nodes[w[1]][0] - mesh.nodes[w[0]][0];
        for &n in w {
            load[2 * n] += traction[0] * len / 2.0;
            load[2 * n + 1] += traction[1] * len / 2.0;
        }
    }
}

fn model(
    mesh: Mesh<Planar>,
    fixed: Vec<usize>,
    load: Vec<f64>,
    pairs: Vec<PairInput>,
    plane: Plane,
) -> Model<Planar> {
    let n_el = mesh.elements.len();
    Model {
        mesh,
        element_material: vec![0; n_el],
        materials: vec![Material::elastic(1000.0, 0.3)],
        section: PlaneSection { plane, thickness: 1.0 },
        fixed_dofs: fixed,
        load,
        patterns: vec![],
        stages: vec![],
        pairs,
        names: Names::default(),
        options: Options::default(),
    }
}

#[test]
fn patch_test_uniform_tension_gives_uniform_stress() {
    // Unit square, x-symmetry on x = 0, y-symmetry on y = 0, traction σ on x = 1 and τ-free:
    // every element must carry exactly σx = 5, σy = 0, τxy = 0 (CST passes the patch test).
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, 4, 4);
    let n = mesh.nodes.len();
    let mut fixed = vec![];
    for i in nodes_where(&mesh, |p| p[0].abs() < 1e-12) {
        fixed.push(2 * i);
    }
    for i in nodes_where(&mesh, |p| p[1].abs() < 1e-12) {
        fixed.push(2 * i + 1);
    }
    let mut load = vec![0.0; 2 * n];
    let mut right = nodes_where(&mesh, |p| (p[0] - 1.0).abs() < 1e-12);
    right.sort_by(|&a, &b| mesh.nodes[a][1].partial_cmp(&mesh.nodes[b][1]).unwrap());
    for w in right.windows(2) {
        let len = mesh.nodes[w[1]][1] - mesh.nodes[w[0]][1];
        load[2 * w[0]] += 5.0 * len / 2.0;
        load[2 * w[1]] += 5.0 * len / 2.0;
    }
    for plane in [Plane::Stress, Plane::Strain] {
        let m = model(mesh.clone(), fixed.clone(), load.clone(), vec![], plane);
        let res = slipstep_core::run(&m, |_| true).unwrap();
        assert_eq!(res.steps.len(), 1, "no contact: one increment");
        let last = res.snapshots.last().unwrap();
        for s in &last.stress {
            assert!(
                (s[0] - 5.0).abs() < 1e-10 && s[1].abs() < 1e-10 && s[3].abs() < 1e-10,
                "{s:?}"
            );
            let sz = if plane == Plane::Strain { 0.3 * 5.0 } else { 0.0 };
            assert!((s[2] - sz).abs() < 1e-10);
        }
        // Exact displacement of the uniform state: u_x = σ(1-ν²)/E · x in plane strain.
        let ex = if plane == Plane::Strain { 5.0 * (1.0 - 0.09) / 1000.0 } else { 5.0 / 1000.0 };
        for (i, p) in m.mesh.nodes.iter().enumerate() {
            assert!((last.u[2 * i] - ex * p[0]).abs() < 1e-12);
        }
        assert!(res.max_equilibrium_residual < 1e-12);
    }
}

#[test]
fn block_on_rigid_flat_closed_from_the_start() {
    // A block resting on the flat y = 0 (all bottom nodes at zero gap: receding contact),
    // held in x by symmetry on x = 0, uniform pressure q on top. Frictionless: uniform
    // σy = −q, and Σλ_n = q·w; the block is held vertically only by contact.
    let (w, h, q) = (2.0, 1.0, 3.0);
    let mesh = rectangle(0.0, 0.0, w, h, 6, 3);
    let n = mesh.nodes.len();
    let fixed: Vec<usize> =
        nodes_where(&mesh, |p| p[0].abs() < 1e-12).iter().map(|i| 2 * i).collect();
    let mut load = vec![0.0; 2 * n];
    top_traction(&mesh, h, [0.0, -q], &mut load);
    for mu in [0.0, 0.5] {
        let pairs = nodes_where(&mesh, |p| p[1].abs() < 1e-12)
            .into_iter()
            .map(|i| PairInput {
                node_a: i,
                node_b: None,
                normal: [0.0, 1.0, 0.0],
                tangents: None,
                gap: 0.0,
                mu,
                contact: 0,
                weights: vec![],
            })
            .collect();
        let m = model(mesh.clone(), fixed.clone(), load.clone(), pairs, Plane::Strain);
        let res = slipstep_core::run(&m, |_| true).unwrap();
        let last = res.snapshots.last().unwrap();
        let total: f64 = last.lambda_n.iter().sum();
        assert!((total - q * w).abs() < 1e-9 * q * w, "Σλ_n = {total}");
        assert!(last.status.iter().all(|&s| s != 0), "all pairs stay closed");
        if mu == 0.0 {
            // Frictionless: lateral Poisson expansion is free, the stress is uniform.
            for s in &last.stress {
                assert!((s[1] + q).abs() < 1e-9 * q && s[0].abs() < 1e-9 * q, "{s:?}");
            }
        } else {
            // With friction the expansion is restrained (σx < 0 near the base), but Coulomb holds.
            for k in 0..last.lambda_n.len() {
                assert!(last.lambda_t[k].abs() <= mu * last.lambda_n[k] * (1.0 + 1e-9) + 1e-12);
            }
        }
    }
}

#[test]
fn flat_punch_gap_closes_at_the_predicted_load() {
    // A column clamped at its top hangs 0.01 above a rigid flat and is pulled down by nodal
    // loads on its bottom row. Without contact the bottom node moves u_y at full load; with
    // contact the first closure must happen at f = 0.01 / |u_y| (the path is linear until then).
    let (w, h) = (1.0, 2.0);
    let mesh = rectangle(0.0, 0.01, w, h, 2, 4);
    let n = mesh.nodes.len();
    let mut fixed = vec![];
    for i in nodes_where(&mesh, |p| (p[1] - 2.01).abs() < 1e-12) {
        fixed.push(2 * i);
        fixed.push(2 * i + 1);
    }
    let bottom = nodes_where(&mesh, |p| (p[1] - 0.01).abs() < 1e-12);
    let mut load = vec![0.0; 2 * n];
    for &i in &bottom {
        load[2 * i + 1] = -10.0;
    }
    // Reference: the same model without contact gives u_y at full load.
    let free = model(mesh.clone(), fixed.clone(), load.clone(), vec![], Plane::Stress);
    let uy_full =
        slipstep_core::run(&free, |_| true).unwrap().snapshots.last().unwrap().u[2 * bottom[0] + 1];
    let pairs = bottom
        .iter()
        .map(|&i| PairInput {
            node_a: i,
            node_b: None,
            normal: [0.0, 1.0, 0.0],
            tangents: None,
            gap: 0.01,
            mu: 0.0,
            contact: 0,
            weights: vec![],
        })
        .collect();
    let m = model(mesh, fixed, load, pairs, Plane::Stress);
    let res = slipstep_core::run(&m, |_| true).unwrap();
    let closes: Vec<_> = res.events.iter().filter(|e| e.kind == EventKind::Close).collect();
    assert!(!closes.is_empty());
    let f_expected = 0.01 / -uy_full;
    assert!(f_expected < 1.0, "test set-up: the gap must close before full load");
    // The first closure happens exactly when the most-displaced bottom node reaches the flat.
    let first = closes[0].load_fraction;
    assert!(
        first <= f_expected * (1.0 + 1e-9),
        "first closure {first} vs uniform-gap estimate {f_expected}"
    );
    let last = res.snapshots.last().unwrap();
    assert!(last.gap.iter().all(|&g| g > -1e-12));
}

#[test]
fn body_free_to_translate_is_a_clear_error() {
    // A block with only x-symmetry and an open gap below: nothing holds it vertically.
    let mesh = rectangle(0.0, 0.1, 1.0, 1.0, 2, 2);
    let n = mesh.nodes.len();
    let fixed: Vec<usize> =
        nodes_where(&mesh, |p| p[0].abs() < 1e-12).iter().map(|i| 2 * i).collect();
    let mut load = vec![0.0; 2 * n];
    top_traction(&mesh, 1.1, [0.0, -1.0], &mut load);
    let pairs = nodes_where(&mesh, |p| (p[1] - 0.1).abs() < 1e-12)
        .into_iter()
        .map(|i| PairInput {
            node_a: i,
            node_b: None,
            normal: [0.0, 1.0, 0.0],
            tangents: None,
            gap: 0.1,
            mu: 0.0,
            contact: 0,
            weights: vec![],
        })
        .collect();
    let m = model(mesh, fixed, load, pairs, Plane::Strain);
    let err = slipstep_core::run(&m, |_| true).unwrap_err().message;
    assert!(err.contains("free to move") && err.contains("translation in y"), "{err}");
}

#[test]
fn initial_penetration_and_negative_mu_are_named() {
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, 1, 1);
    let mut load = vec![0.0; 8];
    load[5] = -1.0;
    let mk = |gap: f64, mu: f64| {
        model(
            mesh.clone(),
            vec![0, 6],
            load.clone(),
            vec![PairInput {
                node_a: 1,
                node_b: None,
                normal: [0.0, 1.0, 0.0],
                tangents: None,
                gap,
                mu,
                contact: 0,
                weights: vec![],
            }],
            Plane::Strain,
        )
    };
    let e = slipstep_core::run(&mk(-0.1, 0.0), |_| true).unwrap_err().message;
    assert!(e.starts_with("initial penetration at contact pair 0"), "{e}");
    let e = slipstep_core::run(&mk(0.0, -0.2), |_| true).unwrap_err().message;
    assert!(e.contains("mu = -0.2"), "{e}");
}

/// Upper block on a lower block (matching interface nodes, zero gaps, node-to-node pairs),
/// lower block clamped at its base, symmetry on x = 0, pressure q on the upper top.
/// Force is conserved across the interface: Σλ_n = q·w_upper.
fn two_blocks(q: f64, wu: f64) -> Model<Planar> {
    let lower = rectangle(0.0, 0.0, 2.0, 1.0, 8, 4);
    let upper = rectangle(0.0, 1.0, wu, 0.5, 4, 2);
    let off = lower.nodes.len();
    let mut mesh = lower.clone();
    mesh.nodes.extend(upper.nodes.iter().copied());
    mesh.elements.extend(upper.elements.iter().map(|t| t.map(|v| v + off)));
    let n = mesh.nodes.len();
    let mut fixed = vec![];
    for i in 0..n {
        let p = mesh.nodes[i];
        if p[0].abs() < 1e-12 {
            fixed.push(2 * i);
        }
        if p[1].abs() < 1e-12 {
            fixed.push(2 * i + 1);
        }
    }
    let mut load = vec![0.0; 2 * n];
    let top: Vec<usize> = (off..n).filter(|&i| (mesh.nodes[i][1] - 1.5).abs() < 1e-12).collect();
    for &i in &top {
        let x = mesh.nodes[i][0];
        let len = if x.abs() < 1e-12 || (x - wu).abs() < 1e-12 { 0.125 } else { 0.25 };
        load[2 * i + 1] = -q * len;
    }
    let mut pairs = vec![];
    for a in off..n {
        if (mesh.nodes[a][1] - 1.0).abs() > 1e-12 {
            continue;
        }
        let b = (0..off)
            .find(|&b| {
                (mesh.nodes[b][0] - mesh.nodes[a][0]).abs() < 1e-12
                    && (mesh.nodes[b][1] - 1.0).abs() < 1e-12
            })
            .unwrap();
        pairs.push(PairInput {
            node_a: a,
            node_b: Some(b),
            normal: [0.0, 1.0, 0.0],
            tangents: None,
            gap: 0.0,
            mu: 0.2,
            contact: 0,
            weights: vec![],
        });
    }
    model(mesh, fixed, load, pairs, Plane::Strain)
}

#[test]
fn two_blocks_conforming_contact_transmit_the_load() {
    // Force is conserved across the interface: Σλ_n = q·w_upper.
    let (q, wu) = (2.0, 1.0);
    let m = two_blocks(q, wu);
    let res = slipstep_core::run(&m, |_| true).unwrap();
    let last = res.snapshots.last().unwrap();
    let total: f64 = last.lambda_n.iter().sum();
    assert!((total - q * wu).abs() < 1e-9 * q * wu, "Σλ_n = {total}");
    for (k, st) in last.status.iter().enumerate() {
        assert!(last.lambda_t[k].abs() <= 0.2 * last.lambda_n[k] + 1e-9, "pair {k} status {st}");
    }
}

#[test]
fn tractionless_body_returns_zero_stress() {
    // Supported square without load: one increment, zero displacement and zero stress.
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, 3, 3);
    let n = mesh.nodes.len();
    let fixed: Vec<usize> = nodes_where(&mesh, |p| p[1].abs() < 1e-12)
        .iter()
        .flat_map(|&i| [2 * i, 2 * i + 1])
        .collect();
    let m = model(mesh, fixed, vec![0.0; 2 * n], vec![], Plane::Strain);
    let res = slipstep_core::run(&m, |_| true).unwrap();
    let last = res.snapshots.last().unwrap();
    assert_eq!(last.load_fraction, 1.0);
    assert!(last.u.iter().all(|&v| v == 0.0));
    assert!(last.stress.iter().all(|s| s.iter().all(|&v| v == 0.0)));
}

/// Unit square of two CSTs on rollers (u_x = 0 on x = 0, u_y = 0 on y = 0): a uniform stress
/// state, loaded on the right edge (uniaxial) or on the top edge (compression).
fn square_on_rollers(
    load_right: f64,
    load_top: f64,
    plane: Plane,
    sy: f64,
    h: f64,
) -> Model<Planar> {
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, 1, 1);
    let mut fixed = vec![];
    for i in nodes_where(&mesh, |p| p[0].abs() < 1e-12) {
        fixed.push(2 * i);
    }
    for i in nodes_where(&mesh, |p| p[1].abs() < 1e-12) {
        fixed.push(2 * i + 1);
    }
    let mut load = vec![0.0; 8];
    for i in nodes_where(&mesh, |p| (p[0] - 1.0).abs() < 1e-12) {
        load[2 * i] += load_right / 2.0;
    }
    for i in nodes_where(&mesh, |p| (p[1] - 1.0).abs() < 1e-12) {
        load[2 * i + 1] += load_top / 2.0;
    }
    let mut m = model(mesh, fixed, load, vec![], plane);
    m.materials[0].yield_stress = sy;
    m.materials[0].hardening = h;
    m.options.snapshots = SnapshotRequest::Times((1..=20).map(|k| k as f64 / 20.0).collect());
    m
}

#[test]
fn uniaxial_plane_stress_follows_the_hardening_line_exactly() {
    // E = 1000, Sy = 2, H' = 250, σ up to 5: both elements yield together at f = Sy/σ = 0.4
    // (a tie), then ε = σ/E + (σ − Sy)/H' exactly (the flow direction does not rotate).
    // Event by event (group_tol = 0): the tie is the subject.
    let (e, sy, h, q) = (1000.0, 2.0, 250.0, 5.0);
    let mut m = square_on_rollers(q, 0.0, Plane::Stress, sy, h);
    m.options.group_tol = 0.0;
    let res = slipstep_core::run(&m, |_| true).unwrap();
    let yields: Vec<_> = res.events.iter().filter(|ev| ev.kind == EventKind::Yield).collect();
    assert_eq!(yields.len(), 2);
    assert!(yields.iter().all(|ev| ev.step == yields[0].step), "tie: one increment");
    assert!((yields[0].load_fraction - sy / q).abs() < 1e-12, "first yield at σe = Sy exactly");
    for snap in &res.snapshots {
        let s = snap.load_fraction * q;
        let strain = s / e + ((s - sy) / h).max(0.0);
        let ux = snap.u[2 * 1]; // node (1, 0)
        assert!(
            (ux - strain).abs() < 1e-12 * strain.max(1e-3),
            "f = {}: {ux} vs {strain}",
            snap.load_fraction
        );
        for (k, st) in snap.stress.iter().enumerate() {
            assert!(
                (st[0] - s).abs() < 1e-9 && st[1].abs() < 1e-9 && st[2].abs() < 1e-9,
                "{st:?} vs σ = {s}"
            );
            assert!((snap.plastic_strain[k] - ((s - sy) / h).max(0.0)).abs() < 1e-12);
        }
    }
    assert!(res.max_drift < 1e-12);
}

#[test]
fn plane_strain_compression_stays_on_the_hardening_line() {
    // Plane strain: σz evolves, so the flow direction rotates and a tangent frozen at an
    // increment's start drifts. With drift control the stresses are integrated and every event
    // lies on σe = Sy + H' εp up to what the equilibrium correction moves along the tangent K
    // holds; the paper's setting drifts more.
    let (sy, h) = (2.0, 250.0);
    let mut m = square_on_rollers(0.0, -6.0, Plane::Strain, sy, h);
    // (tangent_turn, bound): with the tangent renewed at every increment the correction moves
    // the stress along the current flow, a second-order departure (≤ 1e-8 here): 1e-7
    // relative. With a tangent up to θ = tangent_turn off the flow, the correction (at most
    // max_stress_step² of σy: the linearization error of an increment) departs by up to
    // θ × that: 0.05 × 0.05² = 1.25e-4.
    for (turn, bound) in
        [(0.0, 1e-7), (slipstep_core::model::DEFAULT_TANGENT_TURN, 0.05 * 0.05 * 0.05)]
    {
        m.options.tangent_turn = turn;
        let res = slipstep_core::run(&m, |_| true).unwrap();
        let last = res.snapshots.last().unwrap();
        for (k, st) in last.stress.iter().enumerate() {
            let se = slipstep_core::material::von_mises(&nalgebra::Vector6::from_row_slice(st));
            let ep = last.plastic_strain[k];
            assert!(ep > 0.0);
            assert!(
                (se - (sy + h * ep)).abs() < bound * se,
                "turn {turn}: {se} vs {}",
                sy + h * ep
            );
            assert!((st[1] + 6.0).abs() < 1e-9, "equilibrium: σy = −q");
        }
    }
    m.options.tangent_turn = 0.0;
    let res = slipstep_core::run(&m, |_| true).unwrap();
    assert!(res.max_equilibrium_residual < 1e-12);
    assert!(res.max_drift <= 0.05 * 0.05);
    m.options.drift_control = false;
    let exact = slipstep_core::run(&m, |_| true).unwrap();
    assert!(exact.max_drift > res.max_drift);
}

#[test]
fn reduced_elastic_mode_reproduces_the_general_path() {
    // The reduced mode never forms u between events (u = φK#P + K#Wλ + Nα); it must give the
    // same event history, multipliers and fields as the general residual-form path.
    let mut m = two_blocks(2.0, 1.0);
    let a = slipstep_core::run(&m, |_| true).unwrap();
    m.options.reduced_elastic = false;
    let b = slipstep_core::run(&m, |_| true).unwrap();
    assert_eq!(a.events.len(), b.events.len());
    for (x, y) in a.events.iter().zip(&b.events) {
        assert_eq!((x.kind, x.entity), (y.kind, y.entity));
        assert!((x.load_fraction - y.load_fraction).abs() < 1e-12);
    }
    for (x, y) in a.snapshots.iter().zip(&b.snapshots) {
        for k in 0..x.lambda_n.len() {
            assert!(
                (x.lambda_n[k] - y.lambda_n[k]).abs() < 1e-10
                    && (x.lambda_t[k] - y.lambda_t[k]).abs() < 1e-10
            );
        }
        for k in 0..x.u.len() {
            assert!((x.u[k] - y.u[k]).abs() < 1e-12);
        }
    }
}

/// A block of width 2 on the rigid flat y = 0 (all pairs closed, gap 0), pressed by q = 1 and
/// sheared by a traction τ on its top, held by nothing else in x: by equilibrium of the whole
/// block the pairs must carry Σλ_t = −2τ with Σλ_n = 2, so friction holds it iff τ ≤ μ q.
fn sheared_block(mu: f64, tau: f64) -> Model<Planar> {
    let mesh = rectangle(0.0, 0.0, 2.0, 1.0, 4, 2);
    let n = mesh.nodes.len();
    let mut load = vec![0.0; 2 * n];
    top_traction(&mesh, 1.0, [tau, -1.0], &mut load);
    let pairs = nodes_where(&mesh, |p| p[1].abs() < 1e-12)
        .into_iter()
        .map(|i| PairInput {
            node_a: i,
            node_b: None,
            normal: [0.0, 1.0, 0.0],
            tangents: None,
            gap: 0.0,
            mu,
            contact: 0,
            weights: vec![],
        })
        .collect();
    let mut m = model(mesh, vec![], load, pairs, Plane::Strain);
    m.names = Names {
        bodies: vec!["block".into()],
        element_body: vec![0; m.mesh.elements.len()],
        contacts: vec!["base".into()],
        ..Default::default()
    };
    m
}

#[test]
fn the_core_validates_its_options_itself() {
    // Before the core validated its own options, tie_tol = NaN ran 1,200 increments and
    // returned Ok with no event.
    let mut m = sheared_block(0.5, 0.1);
    m.options.tie_tol = f64::NAN;
    let err = slipstep_core::run(&m, |_| true).unwrap_err();
    assert_eq!(err.kind, slipstep_core::error::ErrorKind::Input);
    assert!(err.message.starts_with("options.tie_tol = NaN is not allowed"), "{}", err.message);
    let mut m = sheared_block(0.5, 0.1);
    m.pairs[0].contact = 3;
    assert_eq!(
        slipstep_core::run(&m, |_| true).unwrap_err().kind,
        slipstep_core::error::ErrorKind::Input
    );
}

#[test]
fn shear_beyond_the_friction_limit_is_gross_sliding_of_the_named_body() {
    // τ = 0.6 > μ q = 0.5: the block slides (τ/q > μ at every load level). The message names
    // the body, and under the full load T = 2τ = 1.2 against μN = 0.5 × 2q = 1.
    let err = slipstep_core::run(&sheared_block(0.5, 0.6), |_| true).unwrap_err();
    assert_eq!(err.kind, slipstep_core::error::ErrorKind::GrossSliding, "{}", err.message);
    assert!(err.message.starts_with("body 'block' slides as a whole"), "{}", err.message);
    assert!(err.message.contains("translation in x"), "{}", err.message);
    assert!(
        err.message.contains("T = 1.2000e0") && err.message.contains("μN = 1.0000e0"),
        "{}",
        err.message
    );
    // Frictionless, any tangential load slides the block: capacity μN = 0.
    let err = slipstep_core::run(&sheared_block(0.0, 0.1), |_| true).unwrap_err();
    assert_eq!(err.kind, slipstep_core::error::ErrorKind::GrossSliding, "{}", err.message);
    assert!(err.message.contains("μN = 0.0000e0"), "{}", err.message);
    // Below the limit (τ = 0.25 = μq/2) the block is held: Σλ_t = −2τ, Σλ_n = 2 (equilibrium).
    let res = slipstep_core::run(&sheared_block(0.5, 0.25), |_| true).unwrap();
    assert_eq!(res.stop, StopReason::Completed);
    let last = res.snapshots.last().unwrap();
    let (fn_, ft): (f64, f64) = (last.lambda_n.iter().sum(), last.lambda_t.iter().sum());
    // λ_t is along t = (−n_y, n_x) = (−1, 0): the pairs push the block by −λ_t in x.
    assert!((fn_ - 2.0).abs() < 1e-9 && (ft - 0.5).abs() < 1e-9, "Σλ_n = {fn_}, Σλ_t = {ft}");
}

/// A column [0, 1] × [0.01, 2.01] clamped at its top, hanging 0.01 above the rigid flat y = 0,
/// with a candidate pair at every bottom node; `pull` is the downward force per bottom node.
fn hanging_column(pull: f64, mu: f64) -> (Model<Planar>, Vec<usize>) {
    let mesh = rectangle(0.0, 0.01, 1.0, 2.0, 2, 4);
    let n = mesh.nodes.len();
    let fixed: Vec<usize> = nodes_where(&mesh, |p| (p[1] - 2.01).abs() < 1e-12)
        .into_iter()
        .flat_map(|i| [2 * i, 2 * i + 1])
        .collect();
    let bottom = nodes_where(&mesh, |p| (p[1] - 0.01).abs() < 1e-12);
    let mut load = vec![0.0; 2 * n];
    bottom.iter().for_each(|&i| load[2 * i + 1] = -pull);
    let pairs = bottom
        .iter()
        .map(|&i| PairInput {
            node_a: i,
            node_b: None,
            normal: [0.0, 1.0, 0.0],
            tangents: None,
            gap: 0.01,
            mu,
            contact: 0,
            weights: vec![],
        })
        .collect();
    (model(mesh, fixed, load, pairs, Plane::Stress), bottom)
}

fn stage(factors: &[f64]) -> Stage {
    Stage { name: String::new(), factors: factors.to_vec() }
}

#[test]
fn elastic_load_then_unload_retraces_the_path() {
    // Frictionless and elastic, the path is reversible: unloading to zero returns u and λ to
    // zero (to round-off of the solves: 1e-12 of the largest value), and every pair that closed
    // at load factor f during loading separates at the same factor, i.e. at t = 2 − f.
    let (mut m, _) = hanging_column(10.0, 0.0);
    m.stages = vec![stage(&[1.0]), stage(&[0.0])];
    let res = slipstep_core::run(&m, |_| true).unwrap();
    assert_eq!(res.stop, StopReason::Completed);
    let (loaded, last) =
        (res.snapshots.iter().find(|s| s.time == 1.0).unwrap(), res.snapshots.last().unwrap());
    assert_eq!(last.time, 2.0);
    let umax = loaded.u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let lmax = loaded.lambda_n.iter().fold(0.0f64, |a, v| a.max(*v));
    assert!(umax > 0.0 && lmax > 0.0, "the load must close some pairs");
    assert!(last.u.iter().all(|v| v.abs() <= 1e-12 * umax), "u does not return to 0");
    assert!(last.lambda_n.iter().all(|v| v.abs() <= 1e-12 * lmax), "λ_n does not return to 0");
    let closes: Vec<_> = res.events.iter().filter(|e| e.kind == EventKind::Close).collect();
    assert!(!closes.is_empty());
    for c in closes {
        let sep = res.events.iter().find(|e| e.kind == EventKind::Separate && e.entity == c.entity);
        let t = sep.map_or(2.0, |e| e.time); // the last to close may separate exactly at t = 2
        assert!(
            (t - (2.0 - c.time)).abs() < 1e-9,
            "pair {} closed at {} but separates at {t}",
            c.entity,
            c.time
        );
    }
}

#[test]
fn prescribed_displacement_is_held_by_the_force_that_produces_it() {
    // Force control gives u at the bottom row; prescribing that u instead must give the same
    // fields (1e-9 relative: two different solves of one linear system) and reactions equal to
    // the forces (the supports now supply them; 1e-9 of the force).
    let (mut free, bottom) = hanging_column(10.0, 0.0);
    free.pairs.clear();
    let forced = slipstep_core::run(&free, |_| true).unwrap();
    let u = &forced.snapshots.last().unwrap().u;
    let mut held = free.clone();
    held.load = vec![0.0; u.len()];
    held.patterns = vec![LoadPattern {
        name: "pull".into(),
        displacement: bottom
            .iter()
            .flat_map(|&i| [(2 * i, u[2 * i]), (2 * i + 1, u[2 * i + 1])])
            .collect(),
        ..Default::default()
    }];
    held.options.reduced_elastic = false;
    for reduced in [false, true] {
        held.options.reduced_elastic = reduced;
        let res = slipstep_core::run(&held, |_| true).unwrap();
        let snap = res.snapshots.last().unwrap();
        let umax = u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        assert!(
            snap.u.iter().zip(u).all(|(a, b)| (a - b).abs() <= 1e-9 * umax),
            "reduced = {reduced}: fields differ"
        );
        for &i in &bottom {
            assert!(
                (snap.reaction[2 * i + 1] - (-10.0)).abs() < 1e-9 * 10.0,
                "reaction {} at node {i}",
                snap.reaction[2 * i + 1]
            );
            assert!(snap.reaction[2 * i].abs() < 1e-9 * 10.0);
        }
    }
}

#[test]
fn a_moving_obstacle_equals_the_body_moved_against_it() {
    // Flat moving up by 0.03 into the column clamped at its top, or the column's top moved down
    // by 0.03 onto the fixed flat: the same contact problem seen from two frames, so the same
    // contact forces, events and stresses; displacements differ by the rigid translation.
    let (mut a, _) = hanging_column(0.0, 0.3);
    a.patterns = vec![LoadPattern {
        name: "lift".into(),
        motion: vec![(0, [0.0, 0.03, 0.0])],
        ..Default::default()
    }];
    let top: Vec<usize> = a.fixed_dofs.clone();
    let mut b = a.clone();
    b.fixed_dofs = top.iter().copied().filter(|d| d % 2 == 0).collect();
    b.patterns = vec![LoadPattern {
        name: "press".into(),
        displacement: top.iter().copied().filter(|d| d % 2 == 1).map(|d| (d, -0.03)).collect(),
        ..Default::default()
    }];
    let (ra, rb) =
        (slipstep_core::run(&a, |_| true).unwrap(), slipstep_core::run(&b, |_| true).unwrap());
    let kinds = |r: &RunResult| r.events.iter().map(|e| (e.kind, e.entity)).collect::<Vec<_>>();
    assert_eq!(kinds(&ra), kinds(&rb));
    let (sa, sb) = (ra.snapshots.last().unwrap(), rb.snapshots.last().unwrap());
    let lmax = sa.lambda_n.iter().fold(0.0f64, |m, v| m.max(*v));
    assert!(lmax > 0.0, "the flat must reach the column");
    for k in 0..sa.lambda_n.len() {
        assert!(
            (sa.lambda_n[k] - sb.lambda_n[k]).abs() < 1e-9 * lmax
                && (sa.lambda_t[k] - sb.lambda_t[k]).abs() < 1e-9 * lmax
        );
        assert!((sa.gap[k] - sb.gap[k]).abs() < 1e-12);
    }
    for i in 0..sa.u.len() / 2 {
        assert!(
            (sa.u[2 * i] - sb.u[2 * i]).abs() < 1e-12
                && (sa.u[2 * i + 1] - (sb.u[2 * i + 1] + 0.03)).abs() < 1e-12
        );
    }
}

#[test]
fn path_input_errors_name_the_load_or_stage() {
    let (mut m, bottom) = hanging_column(10.0, 0.0);
    m.stages = vec![stage(&[1.0]), stage(&[1.0])];
    let err = slipstep_core::run(&m, |_| true).unwrap_err();
    assert!(err.message.starts_with("stage 2 changes no load factor"), "{}", err.message);
    m.stages = vec![stage(&[1.0, 0.5])];
    assert!(slipstep_core::run(&m, |_| true)
        .unwrap_err()
        .message
        .contains("has 2 factors for 1 load patterns"));
    m.stages.clear();
    m.patterns = vec![LoadPattern {
        name: "push".into(),
        displacement: vec![(m.fixed_dofs[0], 0.1)],
        ..Default::default()
    }];
    let err = slipstep_core::run(&m, |_| true).unwrap_err();
    assert!(
        err.message.starts_with("load 'push'") && err.message.contains("already held"),
        "{}",
        err.message
    );
    let _ = bottom;
}

// ------------------------------------------------------------------------- axisymmetry

/// Consistent ring loads 2π ∫ N_i r t ds of a uniform traction t on the straight boundary
/// through the nodes `ids` (sorted along it): each segment gives its end i
/// 2π L (2 r_i + r_j)/6 · t (N and r linear along it).
fn ring_traction(mesh: &Mesh<Planar>, mut ids: Vec<usize>, traction: [f64; 2], load: &mut [f64]) {
    let key = |i: &usize| mesh.nodes[*i][0] + mesh.nodes[*i][1];
    ids.sort_by(|a, b| key(a).partial_cmp(&key(b)).unwrap());
    for w in ids.windows(2) {
        let (p, q) = (mesh.nodes[w[0]], mesh.nodes[w[1]]);
        let len = (q[0] - p[0]).hypot(q[1] - p[1]);
        for (i, j) in [(p, q), (q, p)] {
            let share = 2.0 * std::f64::consts::PI * len * (2.0 * i[0] + j[0]) / 6.0;
            let node = if i == p { w[0] } else { w[1] };
            load[2 * node] += traction[0] * share;
            load[2 * node + 1] += traction[1] * share;
        }
    }
}

/// Isotropic stress (σr, σz, σθ, τrz) of the strain (εr = εθ = A, εz = B, γ = 0), E = 1000, ν = 0.3.
fn ring_stress(a: f64, b: f64) -> [f64; 4] {
    let (e, nu) = (1000.0, 0.3);
    let (lame, g) = (e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), e / (2.0 * (1.0 + nu)));
    let sr = 2.0 * (lame + g) * a + lame * b;
    [sr, 2.0 * lame * a + (lame + 2.0 * g) * b, sr, 0.0]
}

#[test]
fn ring_patch_test_reproduces_uniform_radial_and_axial_strain() {
    // u_r = A r, u_z = B z is the exact solution of a cylinder r_in <= r <= r_out, 0 <= z <= 1
    // (held axially on z = 0) under the tractions of its uniform stress (σr = σθ: in
    // equilibrium without body force): the ring element, whose centroid hoop strain is exact
    // for u_r ∝ r and whose weight 2π r̄ A integrates a uniform stress's virtual work exactly,
    // must reproduce it to round-off, on a patch touching the axis (r_in = 0, where the axis
    // nodes are held radially by the engine) and on one away from it.
    let (a, b) = (2e-3, -1e-3);
    let s = ring_stress(a, b);
    for (r_in, width) in [(0.0, 1.0), (0.5, 1.0)] {
        let mesh = rectangle(r_in, 0.0, width, 1.0, 4, 4);
        let n = mesh.nodes.len();
        let fixed: Vec<usize> =
            nodes_where(&mesh, |p| p[1].abs() < 1e-12).iter().map(|i| 2 * i + 1).collect();
        let mut load = vec![0.0; 2 * n];
        ring_traction(
            &mesh,
            nodes_where(&mesh, |p| (p[0] - r_in - width).abs() < 1e-12),
            [s[0], 0.0],
            &mut load,
        );
        ring_traction(
            &mesh,
            nodes_where(&mesh, |p| (p[1] - 1.0).abs() < 1e-12),
            [0.0, s[1]],
            &mut load,
        );
        if r_in > 0.0 {
            ring_traction(
                &mesh,
                nodes_where(&mesh, |p| (p[0] - r_in).abs() < 1e-12),
                [-s[0], 0.0],
                &mut load,
            );
        }
        let m = model(mesh, fixed, load, vec![], Plane::Axisymmetric);
        let res = slipstep_core::run(&m, |_| true).unwrap();
        let last = res.snapshots.last().unwrap();
        // Round-off: displacements O(1e-3) from a solve of a few dozen DOFs; stresses O(1).
        for (i, p) in m.mesh.nodes.iter().enumerate() {
            assert!(
                (last.u[2 * i] - a * p[0]).abs() < 1e-13
                    && (last.u[2 * i + 1] - b * p[1]).abs() < 1e-13,
                "r_in {r_in}, node {i}"
            );
        }
        for st in &last.stress {
            assert!((0..4).all(|k| (st[k] - s[k]).abs() < 1e-10), "r_in {r_in}: {st:?} vs {s:?}");
        }
        assert!(res.max_equilibrium_residual < 1e-12);
    }
}

#[test]
fn ring_body_is_free_only_along_the_axis() {
    // A ring (no node on the axis) needs no radial support: radial translation and rotation
    // strain the hoop direction. Without an axial support it is free to move along the axis.
    let mesh = rectangle(0.5, 0.0, 1.0, 1.0, 2, 2);
    let n = mesh.nodes.len();
    let mut load = vec![0.0; 2 * n];
    ring_traction(&mesh, nodes_where(&mesh, |p| (p[0] - 1.5).abs() < 1e-12), [3.0, 0.0], &mut load);
    let m = model(mesh.clone(), vec![], load.clone(), vec![], Plane::Axisymmetric);
    let err = slipstep_core::run(&m, |_| true).unwrap_err().message;
    assert!(
        err.contains("free to move")
            && err.contains("translation in y")
            && !err.contains("rotation"),
        "{err}"
    );
    let held = vec![2 * nodes_where(&mesh, |p| p[1].abs() < 1e-12)[0] + 1];
    assert!(
        slipstep_core::run(&model(mesh, held, load, vec![], Plane::Axisymmetric), |_| true).is_ok()
    );
}

#[test]
fn ring_element_left_of_the_axis_is_named() {
    let mesh = rectangle(-0.25, 0.0, 1.0, 1.0, 2, 2);
    let n = mesh.nodes.len();
    let mut m = model(mesh, vec![1], vec![0.0; 2 * n], vec![], Plane::Axisymmetric);
    m.section.thickness = f64::NAN; // thickness does not apply to rings: not what is refused here
    let err = slipstep_core::run(&m, |_| true).unwrap_err().message;
    assert!(
        err.starts_with("element 0 has node 0 at r = x = -0.25") && err.contains("x >= 0"),
        "{err}"
    );
}

/// A block of height h resting on the rigid flat y = 0 (a pair of coefficient μ at gap 0
/// on every bottom node), held by nothing else: the load q presses its top, pattern 1 is the
/// traction `shear` on its top.
fn block_on_flat(mesh: Mesh<Planar>, h: f64, q: f64, shear: [f64; 2], mu: f64) -> Model<Planar> {
    let n = mesh.nodes.len();
    let (mut load, mut sheared) = (vec![0.0; 2 * n], vec![0.0; 2 * n]);
    top_traction(&mesh, h, [0.0, -q], &mut load);
    top_traction(&mesh, h, shear, &mut sheared);
    let pairs = nodes_where(&mesh, |p| p[1].abs() < 1e-12)
        .into_iter()
        .map(|i| PairInput {
            node_a: i,
            node_b: None,
            normal: [0.0, 1.0, 0.0],
            tangents: None,
            gap: 0.0,
            mu,
            contact: 0,
            weights: vec![],
        })
        .collect();
    let mut m = model(mesh, vec![], load, pairs, Plane::Stress);
    m.patterns = vec![LoadPattern { name: "shear".into(), force: sheared, ..Default::default() }];
    m.names = Names {
        bodies: vec!["block".into()],
        element_body: vec![0; m.mesh.elements.len()],
        contacts: vec!["base".into()],
        ..Default::default()
    };
    m
}

/// Σ λ_n and Σ λ_t t_x (t = (−1, 0) on the flat) of a snapshot: the contact force on the body.
fn contact_resultant(s: &Snapshot) -> (f64, f64) {
    (s.lambda_n.iter().sum(), -s.lambda_t.iter().sum::<f64>())
}

#[test]
fn a_block_sheared_until_it_tips_stops_there_with_its_results() {
    // Pressed by q, then sheared by −τ on its top until it tips about its corner (0, 0).
    // While two pairs or more are closed the contact resultant lies between them; the last but
    // one separates when it reaches the corner: when the moment about (0, 0) of the loads
    // vanishes, τ s w h = q w w/2 (rigid statics: friction acts at y = 0), t* = 1 + q w/(2 h τ).
    // Beyond there is no equilibrium: the run stops at t*, keeping what it computed. μ = 2.686
    // is far above the τ/q = 0.59 at t*: no slip of the block as a whole.
    let (w, h, q, tau) = (5.14, 4.38, 45.67, 59.37);
    let mut m = block_on_flat(rectangle(0.0, 0.0, w, h, 8, 6), h, q, [-tau, 0.0], 2.686);
    m.stages = vec![stage(&[1.0, 0.0]), Stage { name: "shear".into(), factors: vec![1.0, 1.0] }];
    let res = slipstep_core::run(&m, |_| true).unwrap();
    let t_tip = 1.0 + q * w / (2.0 * h * tau);
    let StopReason::SupportLost { load_fraction: t, .. } = res.stop else {
        panic!("{:?}", res.stop)
    };
    // 1e-9: the event's scale comes from a linear solve (round-off ~1e-12 of the load).
    assert!((t - t_tip).abs() < 1e-9, "stopped at t = {t}, tips at {t_tip}");
    let message = res.stop.message().unwrap();
    assert!(message.starts_with(&format!("support lost at t = {t_tip:.6} (stage 'shear'): body 'block' tips about contact 'base' pair 0 (node 0 at (0.000000, 0.000000))")), "{message}");
    // The results up to there: the last snapshot is the state at t*, balanced by the corner alone.
    let last = res.snapshots.last().unwrap();
    assert_eq!(last.time, t);
    assert_eq!(last.status.iter().filter(|&&c| c != 0).count(), 1, "only the pivot is closed");
    let (fy, fx) = contact_resultant(last);
    // 1e-9 of the load: equilibrium of the whole block (equilibrium_tol).
    assert!(
        (fy - q * w).abs() < 1e-9 * q * w && (fx - tau * w * (t - 1.0)).abs() < 1e-9 * q * w,
        "Σ = ({fx}, {fy})"
    );
}

#[test]
fn a_block_sheared_beyond_friction_slides_at_the_friction_limit() {
    // The tipping block with μ = 0.3: friction holds it until the shear reaches μ times the
    // pressure, τ s w = μ q w, t = 1 + μ q/τ (0.23 of the shear stage, before the tipping at 0.45);
    // beyond, every pair slips and nothing holds it: the run stops there with its results.
    let (w, h, q, tau, mu) = (5.14, 4.38, 45.67, 59.37, 0.3);
    let mut m = block_on_flat(rectangle(0.0, 0.0, w, h, 8, 6), h, q, [-tau, 0.0], mu);
    m.stages = vec![stage(&[1.0, 0.0]), Stage { name: "shear".into(), factors: vec![1.0, 1.0] }];
    let res = slipstep_core::run(&m, |_| true).unwrap();
    let StopReason::SupportLost { load_fraction: t, .. } = res.stop else {
        panic!("{:?}", res.stop)
    };
    assert!((t - (1.0 + mu * q / tau)).abs() < 1e-9, "t = {t}"); // round-off of the event's scale
    let message = res.stop.message().unwrap();
    assert!(message.starts_with(&format!("support lost at t = {t:.6} (stage 'shear'): body 'block' slides as a whole (−translation in x)")), "{message}");
    let (fy, fx) = contact_resultant(res.snapshots.last().unwrap());
    assert!(
        (fy - q * w).abs() < 1e-9 * q * w && (fx - mu * q * w).abs() < 1e-9 * q * w,
        "Σ = ({fx}, {fy})"
    );
}

#[test]
fn a_block_pulled_off_the_flat_lifts_off_where_the_pressure_changes_sign() {
    // Pressed by q, then by −q (suction): every λ is (1 − 2s) × its value at t = 1, so all pairs
    // separate together at t = 1.5, and the block is held by nothing beyond.
    let (w, h) = (2.0, 1.0);
    let mut m = block_on_flat(rectangle(0.0, 0.0, w, h, 4, 2), h, 1.0, [0.0, 0.0], 0.3);
    m.stages = vec![stage(&[1.0, 0.0]), stage(&[-1.0, 0.0])];
    let res = slipstep_core::run(&m, |_| true).unwrap();
    let StopReason::SupportLost { load_fraction: t, .. } = res.stop else {
        panic!("{:?}", res.stop)
    };
    assert!((t - 1.5).abs() < 1e-9, "t = {t}"); // round-off of the separation scale
    let message = res.stop.message().unwrap();
    assert!(
        message.starts_with("support lost at t = 1.500000 (stage 2): body 'block' lifts off")
            && message.contains("its last closed pair (contact 'base' pair"),
        "{message}"
    );
    assert!(res.snapshots.last().unwrap().status.iter().all(|&c| c == 0));
}

/// [0, w] × [0, h], nx × ny cells each cut into four triangles at its centre node: mirror-
/// symmetric about x = w/2, and with nx odd no node lies on that axis.
fn crossed_rectangle(w: f64, h: f64, nx: usize, ny: usize) -> Mesh<Planar> {
    let mut nodes: Vec<[f64; 2]> = (0..=ny)
        .flat_map(|j| (0..=nx).map(move |i| [w * i as f64 / nx as f64, h * j as f64 / ny as f64]))
        .collect();
    let mut triangles = vec![];
    for j in 0..ny {
        for i in 0..nx {
            let a = j * (nx + 1) + i;
            let (b, c, d, e) = (a + 1, a + nx + 2, a + nx + 1, nodes.len());
            nodes.push([w * (i as f64 + 0.5) / nx as f64, h * (j as f64 + 0.5) / ny as f64]);
            triangles.extend([[a, b, e], [b, c, e], [c, d, e], [d, a, e]]);
        }
    }
    Mesh::<Planar>::new(nodes, triangles)
}

#[test]
fn a_pressed_block_whose_pairs_all_slip_is_held_by_friction_not_refused() {
    // A block pressed onto a frictional flat expands (Poisson) and its pairs slip outwards; the
    // mesh is mirror-symmetric with no node on its axis, so with small μ every pair slips and
    // the translation along the flat is undetermined while the forces are not. Checked from the
    // arrays: Σλ_n = q w, no net friction, mirror-symmetric forces, friction pointing inwards
    // (against the expansion), Coulomb's cone. Frictionless, nothing holds the block in x.
    let (w, h, q) = (5.0, 2.0, 1.0);
    let mesh = crossed_rectangle(w, h, 5, 2);
    let bottom = nodes_where(&mesh, |p| p[1].abs() < 1e-12);
    for mu in [0.01, 0.05, 0.1] {
        let res = slipstep_core::run(&block_on_flat(mesh.clone(), h, q, [0.0, 0.0], mu), |_| true)
            .unwrap();
        assert_eq!(res.stop, StopReason::Completed);
        let last = res.snapshots.last().unwrap();
        let (fy, fx) = contact_resultant(last);
        // 1e-12 of the load: a single linear solve's round-off (one stage, proportional path).
        assert!((fy - q * w).abs() < 1e-12 * q * w && fx.abs() < 1e-12 * q * w, "Σ = ({fx}, {fy})");
        for (k, &i) in bottom.iter().enumerate() {
            let mirror = bottom.len() - 1 - k;
            assert!((mesh.nodes[i][0] + mesh.nodes[bottom[mirror]][0] - w).abs() < 1e-12);
            let (ln, lt) = (last.lambda_n[k], last.lambda_t[k]);
            assert!(
                (ln - last.lambda_n[mirror]).abs() < 1e-12 * q * w
                    && (lt + last.lambda_t[mirror]).abs() < 1e-12 * q * w,
                "pair {k} is not the mirror of pair {mirror}"
            );
            assert!(
                -lt * (w / 2.0 - mesh.nodes[i][0]) >= 0.0,
                "pair {k}: friction {} points outwards",
                -lt
            );
            assert!(lt.abs() <= mu * ln * (1.0 + 1e-12), "pair {k} outside the cone");
        }
    }
    let err =
        slipstep_core::run(&block_on_flat(mesh, h, q, [0.0, 0.0], 0.0), |_| true).unwrap_err();
    assert_eq!(err.kind, slipstep_core::error::ErrorKind::FreeBody);
    assert!(
        err.message.starts_with("body 'block' is free to move (translation in x)"),
        "{}",
        err.message
    );
}
