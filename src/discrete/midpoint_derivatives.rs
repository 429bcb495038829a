//! Fast derivatives of the midpoint Ld of a URDF model over one segment z = [qa; qb; h]:
//! the gradient (D1Ld, D2Ld, ∂Ld/∂h) from one adjoint sweep of L
//! ([`crate::model::lagrangian_gradient`]), and its Hessian and contracted third derivative
//! as the Jacobian of that gradient by forward duals, 2n+1 passes in all, where forward duals
//! through Ld need O(n²); or fewer, seeded in groups ([`midpoint_segment_groups`]) with the
//! qa and h columns left out where identities of the midpoint rule give their entries from
//! the others.

use nalgebra::DMatrix;
use num_dual::{Dual, Dual64};

use super::midpoint::midpoint_state_into;
use crate::autodiff::{MultiDual, Scalar, SymmetricGroups, ThirdOrder, VectorFunction};
use crate::model::kinematics::check_len;
use crate::model::{Model, SweepBuffers, lagrangian_gradient, mass_matrix_entries};

/// `$f::<K>(args)` for the lane width K = `$width`, one of [`LANE_WIDTHS`].
macro_rules! with_lane_width {
    ($width:expr, $f:ident($($arg:expr),*)) => {
        match $width {
            4 => $f::<4>($($arg),*),
            6 => $f::<6>($($arg),*),
            8 => $f::<8>($($arg),*),
            10 => $f::<10>($($arg),*),
            12 => $f::<12>($($arg),*),
            14 => $f::<14>($($arg),*),
            _ => $f::<16>($($arg),*),
        }
    };
}

/// The midpoint state and the energy sweep's storage of [`midpoint_ld_gradient`], kept
/// by a caller that evaluates many passes (one per column of a segment's derivatives) so that
/// no pass allocates.
#[derive(Debug)]
pub struct LdBuffers<D> {
    q_mid: Vec<D>,
    v_mid: Vec<D>,
    sweep: SweepBuffers<D>,
}

impl<D> Default for LdBuffers<D> {
    fn default() -> Self {
        LdBuffers {
            q_mid: Vec::new(),
            v_mid: Vec::new(),
            sweep: SweepBuffers::default(),
        }
    }
}

/// The midpoint discrete Lagrangian Ld(qa, qb, h) = h·L(q̄, v̄), q̄ = (qa+qb)/2, v̄ = (qb−qa)/h,
/// and its gradient from one adjoint sweep of L at (q̄, v̄):
/// D1Ld = (h/2)·∂L/∂q − ∂L/∂v, D2Ld = (h/2)·∂L/∂q + ∂L/∂v, ∂Ld/∂h = L − v̄·∂L/∂v.
///
/// `qa`, `qb`, `d1_ld` and `d2_ld` have length `nq` (`d1_ld`, `d2_ld` overwritten, N·m·s per
/// coordinate); `h` in s. Returns (Ld in J·s, ∂Ld/∂h in J), the numbers of
/// [`crate::discrete::ld`], [`crate::discrete::d1_ld`] and [`crate::discrete::d2_ld`].
/// `buffers` holds the working storage ([`LdBuffers`]; any, e.g. `LdBuffers::default()`).
pub fn midpoint_ld_gradient<D: Scalar>(
    model: &Model,
    qa: &[D],
    qb: &[D],
    h: D,
    d1_ld: &mut [D],
    d2_ld: &mut [D],
    buffers: &mut LdBuffers<D>,
) -> (D, D) {
    check_len(model, qa.len(), "qa");
    check_len(model, qb.len(), "qb");
    check_len(model, d1_ld.len(), "d1_ld");
    check_len(model, d2_ld.len(), "d2_ld");
    let LdBuffers {
        q_mid,
        v_mid,
        sweep,
    } = buffers;
    midpoint_state_into(qa, qb, h, q_mid, v_mid);
    // ∂L/∂q and ∂L/∂v are written into the output buffers, then combined in place.
    let lagrangian = lagrangian_gradient(model, q_mid, v_mid, d1_ld, d2_ld, sweep);
    let half_h = h * 0.5;
    let mut ld_partial_h = lagrangian;
    for ((d1, d2), &v) in d1_ld.iter_mut().zip(d2_ld.iter_mut()).zip(v_mid.iter()) {
        let (l_q, l_v) = (*d1, *d2);
        *d1 = half_h * l_q - l_v;
        *d2 = half_h * l_q + l_v;
        ld_partial_h -= v * l_v;
    }
    (h * lagrangian, ld_partial_h)
}

/// The gradient of the midpoint Ld as a [`VectorFunction`]: z = [qa; qb; h] (dim 2n+1) →
/// [D1Ld (n); D2Ld (n); ∂Ld/∂h (1)] (dim 2n+1).
///
/// Its Jacobian is the Hessian of Ld, and its `weighted_hessian` with w = [λ_a; λ_b; 0] the
/// third derivative of Ld contracted with w: the numbers `gradient_hessian_third` gives for
/// [`crate::discrete::MidpointSegment`]. Those O(n²) tiled drivers cost as much as the
/// forward-dual path; [`midpoint_gradient_hessian`] and [`midpoint_third_order`] take the
/// Jacobian column by column instead (2n+1 passes).
#[derive(Debug, Clone, Copy)]
pub struct MidpointGradient<'a> {
    /// The robot.
    pub model: &'a Model,
}

impl VectorFunction for MidpointGradient<'_> {
    fn dim_in(&self) -> usize {
        2 * self.model.nq() + 1
    }
    fn dim_out(&self) -> usize {
        2 * self.model.nq() + 1
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        let n = self.model.nq();
        let (d1, rest) = out.split_at_mut(n);
        let (d2, dh) = rest.split_at_mut(n);
        let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
        dh[0] = midpoint_ld_gradient(self.model, qa, qb, h, d1, d2, &mut LdBuffers::default()).1;
    }
}

/// Value, gradient and Hessian of the midpoint Ld at z = [qa; qb; h] (length 2n+1): the
/// numbers of `gradient_hessian(&MidpointSegment, z)` (Hessian `(2n+1) × (2n+1)`, symmetric),
/// computed as the Jacobian of the adjoint gradient, one [`Dual64`] pass per column.
pub fn midpoint_gradient_hessian(model: &Model, z: &[f64]) -> (f64, Vec<f64>, DMatrix<f64>) {
    let dim = check_segment(model, z, "midpoint_gradient_hessian");
    let mut gradient = vec![0.0; dim];
    let mut hessian = DMatrix::zeros(dim, dim);
    let value = for_each_column(
        model,
        None,
        |i, seeded| Dual64::new(z[i], if seeded { 1.0 } else { 0.0 }),
        |row, col, y| {
            gradient[row] = y.re;
            hessian[(row, col)] = y.eps;
        },
    )
    .re;
    symmetrise(&mut hessian, None);
    (value, gradient, hessian)
}

/// Value, gradient, Hessian and contracted third derivative of the midpoint Ld at
/// z = [qa; qb; h] (length 2n+1), contracted with `dir` (length 2n+1; the NLP passes
/// [λ_a; λ_b; 0]): the same [`ThirdOrder`] as `gradient_hessian_third(&MidpointSegment, z,
/// dir)`, computed as the Jacobian of the adjoint gradient, one pass per column of a
/// [`Dual64`] whose inner ε carries `dir` nested in a [`Dual64`] that seeds the column.
pub fn midpoint_third_order(model: &Model, z: &[f64], dir: &[f64]) -> ThirdOrder {
    let mut out = ThirdOrder::zeros(2 * model.nq() + 1);
    midpoint_third_order_into(model, z, dir, &mut out);
    out
}

/// [`midpoint_third_order`] writing into `out` (sized by [`ThirdOrder::zeros`]`(2n+1)`,
/// overwritten). The Hessian and the contracted third derivative are symmetrised (the
/// Jacobian of a gradient is symmetric up to rounding).
pub fn midpoint_third_order_into(model: &Model, z: &[f64], dir: &[f64], out: &mut ThirdOrder) {
    midpoint_third_order_columns(model, z, dir, None, out);
}

/// [`midpoint_third_order_into`] over the input columns marked in `columns` only (all when
/// `None`; e.g. leaving out inputs fixed by their bounds, whose Hessian entries the solver
/// drops). Entries between two marked inputs are exact; an entry with one marked input is
/// taken from that input's column; entries between unmarked inputs are zero, and so is the
/// value when no column is marked.
pub fn midpoint_third_order_columns(
    model: &Model,
    z: &[f64],
    dir: &[f64],
    columns: Option<&[bool]>,
    out: &mut ThirdOrder,
) {
    let dim = check_segment(model, z, "midpoint_third_order");
    if let Some(c) = columns {
        assert_eq!(
            c.len(),
            dim,
            "midpoint_third_order: one column flag per input"
        );
    }
    assert_eq!(
        dir.len(),
        dim,
        "midpoint_third_order: dir must have length 2 nq + 1"
    );
    assert!(
        out.gradient.len() == dim
            && out.hessian.shape() == (dim, dim)
            && out.contracted.shape() == (dim, dim),
        "midpoint_third_order: buffer from ThirdOrder::zeros(2 nq + 1)"
    );
    out.hessian.fill(0.0);
    out.contracted.fill(0.0);
    let ThirdOrder {
        gradient,
        hessian,
        contracted,
        ..
    } = out;
    let value = for_each_column(
        model,
        columns,
        |i, seeded| nested_input(z, dir, i, seeded),
        |row, col, y| {
            gradient[row] = y.re.re;
            hessian[(row, col)] = y.re.eps;
            contracted[(row, col)] = y.eps.eps;
        },
    );
    out.value = value.re.re;
    symmetrise(&mut out.hessian, columns);
    symmetrise(&mut out.contracted, columns);
}

/// How the column groups of a segment are swept.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroupSweeps {
    /// All groups' directions at once, in the lanes of one [`MultiDual`] sweep (batches of
    /// up to 16 groups, padded to an even width of 4 to 16 lanes): each pose, sine and
    /// cosine of the tree once per batch. The same numbers, to the bit, as `PerGroup`.
    Lanes,
    /// One energy sweep per group (`Dual64`, `Dual<Dual64>`): the reference.
    PerGroup,
}

/// [`midpoint_gradient_hessian`] with the columns seeded by `groups` (of the Hessian of
/// Ld's dependency pattern): the product of the Hessian with each group's seed, each entry
/// read where its group shows it alone (see [`SymmetricGroups`]), the groups swept as
/// `sweeps` says.
pub fn midpoint_gradient_hessian_grouped(
    model: &Model,
    z: &[f64],
    groups: &SymmetricGroups,
    sweeps: GroupSweeps,
) -> (Vec<f64>, DMatrix<f64>) {
    let dim = check_segment(model, z, "midpoint_gradient_hessian_grouped");
    let mut gradient = vec![0.0; dim];
    let mut products = DMatrix::zeros(dim, groups.groups().len());
    match sweeps {
        GroupSweeps::PerGroup => {
            for_each_group(
                model,
                groups,
                |i, seeded| Dual64::new(z[i], if seeded { 1.0 } else { 0.0 }),
                |row, g, y| {
                    gradient[row] = y.re;
                    products[(row, g)] = y.eps;
                },
            );
        }
        GroupSweeps::Lanes => {
            for (first, batch, width) in lane_batches(groups.groups()) {
                let out = (&mut gradient[..], &mut products);
                with_lane_width!(width, products_in_lanes(model, z, batch, first, out));
            }
        }
    }
    let mut hessian = DMatrix::zeros(dim, dim);
    groups.recover(&products, &mut hessian);
    let (translated, derived) = unseeded_qa(model, groups.unseeded());
    let derive_h = groups.unseeded()[dim - 1];
    let h = z[dim - 1];
    translation_columns(&translated, Some(&gradient), h, !derive_h, &mut hessian);
    qa_block_from_identity(model, z, None, &derived, &mut hessian, None);
    if derive_h {
        h_entries_from_scaling(z, &gradient, None, &mut hessian, None);
    }
    (gradient, hessian)
}

/// [`midpoint_third_order`] with the columns seeded by `groups` (see
/// [`midpoint_gradient_hessian_grouped`]); entries with a column outside every group are
/// zero (where [`midpoint_third_order_columns`] reads those with one marked column).
pub fn midpoint_third_order_grouped(
    model: &Model,
    z: &[f64],
    dir: &[f64],
    groups: &SymmetricGroups,
    sweeps: GroupSweeps,
) -> ThirdOrder {
    let dim = check_segment(model, z, "midpoint_third_order_grouped");
    assert_eq!(
        dir.len(),
        dim,
        "midpoint_third_order: dir must have length 2 nq + 1"
    );
    let mut out = ThirdOrder::zeros(dim);
    let count = groups.groups().len();
    let (mut first, mut second) = (DMatrix::zeros(dim, count), DMatrix::zeros(dim, count));
    let gradient = &mut out.gradient;
    out.value = match sweeps {
        GroupSweeps::PerGroup => for_each_group(
            model,
            groups,
            |i, seeded| nested_input(z, dir, i, seeded),
            |row, g, y| {
                gradient[row] = y.re.re;
                first[(row, g)] = y.re.eps;
                second[(row, g)] = y.eps.eps;
            },
        )
        .map_or(0.0, |v| v.re.re),
        GroupSweeps::Lanes => {
            let mut value = 0.0;
            for (at, batch, width) in lane_batches(groups.groups()) {
                let out = (&mut gradient[..], &mut first, &mut second);
                value = with_lane_width!(
                    width,
                    third_products_in_lanes(model, z, dir, batch, at, out)
                );
            }
            value
        }
    };
    groups.recover(&first, &mut out.hessian);
    groups.recover(&second, &mut out.contracted);
    let (translated, derived) = unseeded_qa(model, groups.unseeded());
    let derive_h = groups.unseeded()[dim - 1];
    let h = z[dim - 1];
    translation_columns(
        &translated,
        Some(&out.gradient),
        h,
        !derive_h,
        &mut out.hessian,
    );
    translation_columns(&translated, None, h, !derive_h, &mut out.contracted);
    qa_block_from_identity(
        model,
        z,
        Some(dir),
        &derived,
        &mut out.hessian,
        Some(&mut out.contracted),
    );
    if derive_h {
        h_entries_from_scaling(
            z,
            &out.gradient,
            Some(dir),
            &mut out.hessian,
            Some(&mut out.contracted),
        );
    }
    out
}

/// Column groups for the Hessian of one segment's Ld (`pattern`: its dependency pattern,
/// (2n+1) × (2n+1), over z = [qa; qb; h]; `columns`: the inputs whose entries are needed;
/// `translations`: the coordinates Ld's Lagrangian depends on at most linearly, length n),
/// leaving columns unseeded where that saves passes, their entries from identities of the
/// midpoint rule: the qa columns of translations, minus their qb columns
/// ([`translation_columns`]); other qa columns, whose qa–qa block comes from
/// [`qa_block_from_identity`] and whose entries with qb from the qb columns; and, when every
/// column is needed, the h column, whose entries follow from the q blocks and the gradient
/// ([`h_entries_from_scaling`]). Columns filled whole (translations' qa, h) leave the pattern
/// the groups are built for. Tries leaving out every other qa column but the k most coupled
/// ones (a floating base's rotations, read from their own columns so that legs can share
/// groups), k = 0…n, and keeps the fewest passes (ties: more unseeded).
pub fn midpoint_segment_groups(
    pattern: &[bool],
    columns: &[bool],
    translations: &[bool],
) -> SymmetricGroups {
    let n = translations.len();
    let dim = 2 * n + 1;
    assert_eq!(
        columns.len(),
        dim,
        "midpoint_segment_groups: one flag per input"
    );
    let degree = |j: usize| {
        (0..dim)
            .filter(|&i| pattern[i * dim + j] || pattern[j * dim + i])
            .count()
    };
    // Columns filled whole: the h entries are derived from whole q rows, so only when every
    // column is needed; a translation's qa column from its qb column, when both are needed.
    let derive_h = columns.iter().all(|&c| c);
    let translated: Vec<usize> = (0..n)
        .filter(|&j| translations[j] && columns[j] && columns[n + j])
        .collect();
    let mut grouped_pattern = pattern.to_vec();
    for whole in translated
        .iter()
        .copied()
        .chain(derive_h.then_some(dim - 1))
    {
        for i in 0..dim {
            grouped_pattern[i * dim + whole] = false;
            grouped_pattern[whole * dim + i] = false;
        }
    }
    // Other qa columns that can be derived: needed, with their qb column needed too.
    let mut derivable: Vec<usize> = (0..n)
        .filter(|&j| !translated.contains(&j) && columns[j] && columns[n + j])
        .collect();
    derivable.sort_by_key(|&j| std::cmp::Reverse(degree(j)));
    let mut best: Option<SymmetricGroups> = None;
    for kept in 0..=derivable.len() {
        let mut unseeded = vec![false; dim];
        unseeded[dim - 1] = derive_h;
        for &j in translated.iter().chain(&derivable[kept..]) {
            unseeded[j] = true;
        }
        let groups =
            SymmetricGroups::with_unseeded(dim, &grouped_pattern, Some(columns), &unseeded);
        if best
            .as_ref()
            .is_none_or(|b| groups.groups().len() < b.groups().len())
        {
            best = Some(groups);
        }
    }
    best.unwrap_or_else(|| SymmetricGroups::new(dim, pattern, Some(columns)))
}

/// The unseeded qa columns of a segment's groups, split into translations (filled by
/// [`translation_columns`]) and the others ([`qa_block_from_identity`]), as
/// [`midpoint_segment_groups`] chose them.
fn unseeded_qa(model: &Model, unseeded: &[bool]) -> (Vec<usize>, Vec<usize>) {
    let translations = model.translation_coordinates();
    (0..model.nq())
        .filter(|&j| unseeded[j])
        .partition(|&j| translations[j])
}

/// Fills the qa columns `translated` of a segment's Hessian (or of its contracted third
/// derivative) from their qb columns. L depends on a translation c at most linearly, so
/// ∂/∂q̄_c = ∂/∂qa_c + ∂/∂qb_c of the gradient [(h/2)L_q − L_v; (h/2)L_q + L_v; L − v̄·L_v] is
/// [0; 0; L_q,c]: H[x, qa_c] = −H[x, qb_c] on the q rows and H[h, qa_c] = L_q,c − H[h, qb_c]
/// with L_q,c = (D1Ld + D2Ld)_c/h, a constant (zero derivative: `gradient` None for the
/// contracted matrix). The h row is left alone when `fill_h` is false (h filled later, or
/// not needed).
fn translation_columns(
    translated: &[usize],
    gradient: Option<&[f64]>,
    h: f64,
    fill_h: bool,
    m: &mut DMatrix<f64>,
) {
    let dim = m.nrows();
    let n = (dim - 1) / 2;
    for &c in translated {
        for x in (0..2 * n).filter(|x| !translated.contains(x)) {
            let value = -m[(x, n + c)];
            m[(x, c)] = value;
            m[(c, x)] = value;
        }
    }
    for &c in translated {
        for &d in translated {
            m[(c, d)] = -m[(c, n + d)];
        }
        if fill_h {
            let l_q = gradient.map_or(0.0, |g| (g[c] + g[n + c]) / h);
            let value = l_q - m[(dim - 1, n + c)];
            m[(dim - 1, c)] = value;
            m[(c, dim - 1)] = value;
        }
    }
}

/// Fills the h row and column of a segment's Hessian (and of its third derivative
/// contracted with `dir`, when given) from its q blocks, complete, and the gradient
/// (D1Ld, D2Ld first). Moving (qa, qb, h) along (−Δ/2, Δ/2, h), Δ = qb − qa, keeps q̄ and
/// v̄ and scales h, so D1Ld = (h/2)·L_q − L_v and D2Ld = (h/2)·L_q + L_v change by
/// (h/2)·L_q = (D1Ld + D2Ld)/2 and ∂Ld/∂h = L − v̄·L_v not at all: for a row x of qa or qb
/// (coordinate r), h·H[x, h] = (D1Ld + D2Ld)_r/2 − ½·Σ_j (H[x, qb_j] − H[x, qa_j])·Δ_j,
/// and h·H[h, h] = −½·Σ_j (H[h, qb_j] − H[h, qa_j])·Δ_j; their derivatives along `dir`
/// give the contracted entries.
fn h_entries_from_scaling(
    z: &[f64],
    gradient: &[f64],
    dir: Option<&[f64]>,
    hessian: &mut DMatrix<f64>,
    contracted: Option<&mut DMatrix<f64>>,
) {
    let dim = z.len();
    let n = (dim - 1) / 2;
    let (hcol, h) = (dim - 1, z[dim - 1]);
    let delta: Vec<f64> = (0..n).map(|j| z[n + j] - z[j]).collect();
    // ½·Σ_j (m[x, qb_j] − m[x, qa_j])·w_j.
    let spread = |m: &DMatrix<f64>, x: usize, w: &[f64]| {
        0.5 * (0..n)
            .map(|j| (m[(x, n + j)] - m[(x, j)]) * w[j])
            .sum::<f64>()
    };
    for x in 0..2 * n {
        let r = x % n;
        let value = (0.5 * (gradient[r] + gradient[n + r]) - spread(hessian, x, &delta)) / h;
        hessian[(x, hcol)] = value;
        hessian[(hcol, x)] = value;
    }
    hessian[(hcol, hcol)] = -spread(hessian, hcol, &delta) / h;
    let (Some(dir), Some(t)) = (dir, contracted) else {
        return;
    };
    let d_delta: Vec<f64> = (0..n).map(|j| dir[n + j] - dir[j]).collect();
    let along = |x: usize| (0..dim).map(|k| hessian[(x, k)] * dir[k]).sum::<f64>();
    for x in 0..2 * n {
        let r = x % n;
        let value = (0.5 * (along(r) + along(n + r))
            - spread(t, x, &delta)
            - spread(hessian, x, &d_delta)
            - dir[hcol] * hessian[(x, hcol)])
            / h;
        t[(x, hcol)] = value;
        t[(hcol, x)] = value;
    }
    t[(hcol, hcol)] = (-spread(t, hcol, &delta)
        - spread(hessian, hcol, &d_delta)
        - dir[hcol] * hessian[(hcol, hcol)])
        / h;
}

/// Fills the qa–qa block of a segment's Hessian (and of its third derivative contracted
/// with `dir`, when given) between the qa columns `derived`, from the qb entries already in
/// place. With Ld = h·L(q̄, v̄), q̄ = (qa+qb)/2, v̄ = (qb−qa)/h, and
/// L_vv = M(q̄) (the kinetic energy is quadratic in v̄, the potential free of it):
/// H_aa = h/4·L_qq − ½(L_qv + L_vq) + M/h, H_bb = h/4·L_qq + ½(L_qv + L_vq) + M/h and
/// H_ab = h/4·L_qq + ½(L_qv − L_vq) − M/h, so H_aa = H_ab + H_abᵀ − H_bb + (4/h)·M(q̄),
/// an identity in (qa, qb, h) whose derivative along `dir` gives the contracted block with
/// d/d(dir)[(4/h)·M(q̄)] in place of (4/h)·M(q̄).
fn qa_block_from_identity(
    model: &Model,
    z: &[f64],
    dir: Option<&[f64]>,
    derived: &[usize],
    hessian: &mut DMatrix<f64>,
    contracted: Option<&mut DMatrix<f64>>,
) {
    let n = model.nq();
    if derived.is_empty() {
        return;
    }
    // (4/h)·M(q̄) and its derivative along dir, in one Dual64 evaluation.
    let lift = |i: usize| Dual64::new(z[i], dir.map_or(0.0, |d| d[i]));
    let qa: Vec<Dual64> = (0..n).map(lift).collect();
    let qb: Vec<Dual64> = (n..2 * n).map(lift).collect();
    let h = lift(2 * n);
    let (mut q_mid, mut v_mid) = (Vec::new(), Vec::new());
    midpoint_state_into(&qa, &qb, h, &mut q_mid, &mut v_mid);
    let mut mass = Vec::new();
    mass_matrix_entries(model, &q_mid, &mut mass);
    let four_over_h = Dual64::from(4.0) / h;
    let fill = |m: &mut DMatrix<f64>, part: fn(Dual64) -> f64| {
        for (a, &r) in derived.iter().enumerate() {
            for &c in &derived[..=a] {
                let value = m[(r, n + c)] + m[(c, n + r)] - m[(n + r, n + c)]
                    + part(four_over_h * mass[r * n + c]);
                m[(r, c)] = value;
                m[(c, r)] = value;
            }
        }
    };
    fill(hessian, |d| d.re);
    if let Some(t) = contracted {
        fill(t, |d| d.eps);
    }
}

/// [`for_each_column`] with one pass per column group, all of the group's inputs seeded;
/// `store` gets (row, group, value). Returns Ld from the last pass (`None` without groups).
fn for_each_group<S: Scalar>(
    model: &Model,
    groups: &SymmetricGroups,
    lift: impl Fn(usize, bool) -> S,
    mut store: impl FnMut(usize, usize, &S),
) -> Option<S> {
    let mut sweep = SegmentSweep::new(model, |i| lift(i, false));
    let mut value = None;
    for (g, members) in groups.groups().iter().enumerate() {
        let ld = sweep.run(
            model,
            std::slice::from_ref(members),
            |i, lane| lift(i, lane.is_some()),
            |row, y| store(row, g, y),
        );
        value = Some(ld);
    }
    value
}

/// Lane widths of [`GroupSweeps::Lanes`]: a segment's groups are swept in batches, each as
/// wide as the narrowest width that holds the groups left (the widest when none does). Every
/// padded lane costs as much as a used one, so the widths are close together.
const LANE_WIDTHS: [usize; 7] = [4, 6, 8, 10, 12, 14, 16];

/// The batches of [`GroupSweeps::Lanes`]: (first group, the batch's groups, lane width).
fn lane_batches(groups: &[Vec<usize>]) -> Vec<(usize, &[Vec<usize>], usize)> {
    let widest = LANE_WIDTHS[LANE_WIDTHS.len() - 1];
    let mut batches = Vec::new();
    let mut first = 0;
    while first < groups.len() {
        let left = groups.len() - first;
        let width = LANE_WIDTHS
            .into_iter()
            .find(|&w| w >= left)
            .unwrap_or(widest);
        let taken = left.min(width);
        batches.push((first, &groups[first..first + taken], width));
        first += taken;
    }
    batches
}

/// One [`MultiDual`] sweep of the adjoint gradient with group `first + k` of `batch` seeded
/// along lane k (at most K groups): writes the gradient and the products of the Hessian with
/// the groups' seeds (columns `first..first + batch.len()` of `products`).
fn products_in_lanes<const K: usize>(
    model: &Model,
    z: &[f64],
    batch: &[Vec<usize>],
    first: usize,
    (gradient, products): (&mut [f64], &mut DMatrix<f64>),
) {
    let mut sweep = SegmentSweep::new(model, |i| MultiDual::<K>::constant(z[i]));
    sweep.run(
        model,
        batch,
        |i, lane| MultiDual::seeded(z[i], lane),
        |row, y| {
            gradient[row] = y.re;
            for (k, &e) in y.eps[..batch.len()].iter().enumerate() {
                products[(row, first + k)] = e;
            }
        },
    );
}

/// [`products_in_lanes`] for the Hessian and the contracted third derivative: one sweep of
/// `Dual<MultiDual<K>>`, the outer ε carrying `dir` (shared by the lanes), lane k the seed
/// of group `first + k`, as `Dual<Dual64>` per group. Writes the gradient, the Hessian's
/// products (`first`) and the contracted third derivative's (`second`); returns Ld.
fn third_products_in_lanes<const K: usize>(
    model: &Model,
    z: &[f64],
    dir: &[f64],
    batch: &[Vec<usize>],
    at: usize,
    (gradient, first, second): (&mut [f64], &mut DMatrix<f64>, &mut DMatrix<f64>),
) -> f64 {
    let lift = |i: usize, lane: Option<usize>| {
        Dual::new(
            MultiDual::<K>::seeded(z[i], lane),
            MultiDual::constant(dir[i]),
        )
    };
    let mut sweep = SegmentSweep::new(model, |i| lift(i, None));
    let value = sweep.run(model, batch, lift, |row, y| {
        gradient[row] = y.re.re;
        for k in 0..batch.len() {
            first[(row, at + k)] = y.re.eps[k];
            second[(row, at + k)] = y.eps.eps[k];
        }
    });
    value.re.re
}

/// The inputs z = [qa; qb; h] of a segment's passes, lifted, and the storage of the adjoint
/// gradient, kept from pass to pass so that no pass allocates.
struct SegmentSweep<S> {
    zd: Vec<S>,
    d1: Vec<S>,
    d2: Vec<S>,
    buffers: LdBuffers<S>,
}

impl<S: Scalar> SegmentSweep<S> {
    /// The inputs lifted by `constant(i)` (no derivative seeded).
    fn new(model: &Model, constant: impl Fn(usize) -> S) -> Self {
        let n = model.nq();
        SegmentSweep {
            zd: (0..2 * n + 1).map(constant).collect(),
            d1: vec![S::from(0.0); n],
            d2: vec![S::from(0.0); n],
            buffers: LdBuffers::default(),
        }
    }

    /// One pass of the adjoint gradient with the inputs of `lanes[k]` lifted by
    /// `lift(i, Some(k))` (the others as constructed, restored afterwards); `store` gets
    /// every output (row, value) of [D1Ld; D2Ld; ∂Ld/∂h]. Returns Ld.
    fn run<C: AsRef<[usize]>>(
        &mut self,
        model: &Model,
        lanes: &[C],
        lift: impl Fn(usize, Option<usize>) -> S,
        mut store: impl FnMut(usize, &S),
    ) -> S {
        let n = model.nq();
        for (k, members) in lanes.iter().enumerate() {
            for &c in members.as_ref() {
                self.zd[c] = lift(c, Some(k));
            }
        }
        let zd = &self.zd;
        let (qa, qb, h) = (&zd[..n], &zd[n..2 * n], zd[2 * n]);
        let (ld, dh) = midpoint_ld_gradient(
            model,
            qa,
            qb,
            h,
            &mut self.d1,
            &mut self.d2,
            &mut self.buffers,
        );
        for members in lanes {
            for &c in members.as_ref() {
                self.zd[c] = lift(c, None);
            }
        }
        for (row, y) in self.d1.iter().chain(&self.d2).chain([&dh]).enumerate() {
            store(row, y);
        }
        ld
    }
}

/// Input `i` of z = [qa; qb; h] for a `Dual<Dual64>` pass: the inner ε seeds its column
/// (when `seeded`), the outer ε carries `dir`.
fn nested_input(z: &[f64], dir: &[f64], i: usize, seeded: bool) -> Dual<Dual64> {
    Dual::new(
        Dual64::new(z[i], if seeded { 1.0 } else { 0.0 }),
        Dual64::from(dir[i]),
    )
}

/// Checks the segment length 2n+1 (a caller's programming error otherwise) and returns it.
fn check_segment(model: &Model, z: &[f64], what: &str) -> usize {
    let dim = 2 * model.nq() + 1;
    assert_eq!(
        z.len(),
        dim,
        "{what}: z has length {} but the segment [qa; qb; h] has 2 nq + 1 = {dim}",
        z.len()
    );
    dim
}

/// Evaluates the adjoint gradient of Ld once per input column of z = [qa; qb; h]
/// (dim 2n+1), the inputs lifted by `lift(i, seeded)` with `seeded` true for the column,
/// and hands every output (row, column, value) to `store`. Returns Ld from the last pass.
///
/// One column per pass with an unboxed nested dual beat tiles of `num-dual`'s vector duals
/// (whose `Option`-wrapped derivative vectors cost more than their width saves) by 1.4–3×
/// on this machine (benches/del_segment_paths.rs).
fn for_each_column<S: Scalar>(
    model: &Model,
    columns: Option<&[bool]>,
    lift: impl Fn(usize, bool) -> S,
    mut store: impl FnMut(usize, usize, &S),
) -> S {
    let dim = 2 * model.nq() + 1;
    let mut sweep = SegmentSweep::new(model, |i| lift(i, false));
    let mut value = S::from(0.0);
    for col in (0..dim).filter(|&c| columns.is_none_or(|m| m[c])) {
        value = sweep.run(
            model,
            &[[col]],
            |i, lane| lift(i, lane.is_some()),
            |row, y| store(row, col, y),
        );
    }
    value
}

/// Replaces a square matrix by (A + Aᵀ)/2 where both columns were computed (all when
/// `columns` is `None`), and mirrors the computed column's entry where only one was.
fn symmetrise(a: &mut DMatrix<f64>, columns: Option<&[bool]>) {
    let n = a.nrows();
    let computed = |c: usize| columns.is_none_or(|m| m[c]);
    for i in 0..n {
        for j in 0..i {
            let value = match (computed(i), computed(j)) {
                (true, true) => 0.5 * (a[(i, j)] + a[(j, i)]),
                (false, true) => a[(i, j)],
                (true, false) => a[(j, i)],
                (false, false) => 0.0,
            };
            a[(i, j)] = value;
            a[(j, i)] = value;
        }
    }
}
