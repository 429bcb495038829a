//! Fewer derivative passes for symmetric matrices of known sparsity (Hessians): columns that
//! never share a row where it matters are seeded together, and each entry is read from a
//! product H·s_g (s_g the sum of a group's unit vectors) at a row where no other column of
//! the group has a structural nonzero, on either side of the diagonal (symmetry: H[i, j] at
//! row i of j's group, or at row j of i's group). The pattern comes from the dependency
//! trace (`transcription::structure`), never from values.
//!
//! A robot's legs couple only through the base, so a leg joint's column shares a group with
//! the same joint of the other legs, and the base rows, which see every leg, are read from
//! the base columns' side: HAMR's 77-input segment Hessian takes 33 passes instead of 77.

use nalgebra::DMatrix;
use num_dual::HyperDualSVec64;

use super::{ScalarFunction, TILE};

/// Where one lower entry (i, j ≤ i) of the matrix is read: from `(group, row)` products,
/// averaged when it can be read on both sides of the diagonal.
#[derive(Debug, Clone, PartialEq)]
struct Read {
    i: usize,
    j: usize,
    from: Vec<(usize, usize)>,
}

/// Column groups of a symmetric `dim × dim` pattern and where each entry is read.
#[derive(Debug, Clone, PartialEq)]
pub struct SymmetricGroups {
    dim: usize,
    groups: Vec<Vec<usize>>,
    reads: Vec<Read>,
    /// Rows read from each group.
    rows: Vec<Vec<usize>>,
    /// Columns never seeded (see [`SymmetricGroups::with_unseeded`]).
    unseeded: Vec<bool>,
}

impl SymmetricGroups {
    /// Groups for the symmetric pattern `pattern` (`dim × dim`, row-major; an entry counts
    /// when either (i, j) or (j, i) is set), over the columns marked in `columns` (all when
    /// `None`). Entries between two marked columns are exact; the others (rows and columns
    /// of fixed variables, whose entries the solver drops) are left zero, since reading
    /// them would keep every column apart from an unmarked one that meets them all, like a
    /// fixed time step.
    pub fn new(dim: usize, pattern: &[bool], columns: Option<&[bool]>) -> Self {
        Self::with_unseeded(dim, pattern, columns, &vec![false; dim])
    }

    /// [`SymmetricGroups::new`] with the columns marked in `unseeded` (length `dim`) in no
    /// group: their entries with a seeded column are read from the seeded column's side,
    /// and entries between two of them are left to the caller (zero in
    /// [`SymmetricGroups::recover`]), who knows them from the others (the midpoint
    /// segment's qa–qa block, `crate::discrete::midpoint_derivatives`).
    pub fn with_unseeded(
        dim: usize,
        pattern: &[bool],
        columns: Option<&[bool]>,
        unseeded: &[bool],
    ) -> Self {
        assert_eq!(
            pattern.len(),
            dim * dim,
            "SymmetricGroups: pattern is dim × dim"
        );
        assert_eq!(unseeded.len(), dim, "SymmetricGroups: one flag per column");
        let marked = |j: usize| columns.is_none_or(|m| m[j]);
        let seedable = |j: usize| marked(j) && !unseeded[j];
        let nz = |i: usize, j: usize| {
            (pattern[i * dim + j] || pattern[j * dim + i])
                && marked(i)
                && marked(j)
                && !(unseeded[i] && unseeded[j])
        };
        let neighbours: Vec<Vec<usize>> = (0..dim)
            .map(|j| (0..dim).filter(|&i| nz(i, j)).collect())
            .collect();
        // Group of each column: None while pending (or never, if unmarked).
        let mut group: Vec<Option<usize>> = vec![None; dim];
        let mut groups: Vec<Vec<usize>> = Vec::new();
        // Whether group g, read at row i, shows x's entry alone.
        let clean = |groups: &[Vec<usize>], g: usize, i: usize, x: usize| {
            groups[g].iter().all(|&y| y == x || !nz(i, y))
        };
        // A pair can still be read: from a side whose group is clean there, or a side still
        // pending (which can always take a group of its own).
        let readable = |groups: &[Vec<usize>], group: &[Option<usize>], a: usize, b: usize| {
            let side = |col: usize, row: usize| match group[col] {
                Some(g) => clean(groups, g, row, col),
                None => seedable(col),
            };
            side(b, a) || side(a, b)
        };
        let mut order: Vec<usize> = (0..dim).filter(|&j| seedable(j)).collect();
        order.sort_by_key(|&j| std::cmp::Reverse(neighbours[j].len()));
        for &j in &order {
            let mut chosen = groups.len();
            for g in 0..groups.len() {
                groups[g].push(j);
                group[j] = Some(g);
                let ok = neighbours[j].iter().all(|&i| {
                    groups[g]
                        .iter()
                        .filter(|&&x| nz(i, x))
                        .all(|&x| readable(&groups, &group, i, x))
                }) && neighbours[j]
                    .iter()
                    .all(|&y| readable(&groups, &group, j, y));
                groups[g].pop();
                group[j] = None;
                if ok {
                    chosen = g;
                    break;
                }
            }
            if chosen == groups.len() {
                groups.push(Vec::new());
            }
            groups[chosen].push(j);
            group[j] = Some(chosen);
        }
        let mut reads = Vec::new();
        let mut rows = vec![Vec::new(); groups.len()];
        for i in 0..dim {
            for j in (0..=i).filter(|&j| nz(i, j)) {
                let mut from = Vec::new();
                for (col, row) in [(j, i), (i, j)] {
                    if let Some(g) = group[col]
                        && clean(&groups, g, row, col)
                        && !from.contains(&(g, row))
                    {
                        from.push((g, row));
                    }
                }
                assert!(
                    !from.is_empty(),
                    "SymmetricGroups: entry ({i}, {j}) unreadable"
                );
                for &(g, row) in &from {
                    if !rows[g].contains(&row) {
                        rows[g].push(row);
                    }
                }
                reads.push(Read { i, j, from });
            }
        }
        SymmetricGroups {
            dim,
            groups,
            reads,
            rows,
            unseeded: unseeded.to_vec(),
        }
    }

    /// The columns in no group by construction ([`SymmetricGroups::with_unseeded`]).
    pub fn unseeded(&self) -> &[bool] {
        &self.unseeded
    }

    /// The column groups (one product H·s_g per group).
    pub fn groups(&self) -> &[Vec<usize>] {
        &self.groups
    }

    /// Whether seeding by groups saves passes over one column per pass (columns seeded
    /// together, or columns left unseeded).
    pub fn compresses(&self) -> bool {
        self.groups.iter().any(|g| g.len() > 1) || self.unseeded.iter().any(|&u| u)
    }

    /// The symmetric matrix from its products: `products[(row, g)]` = (H·s_g)[row]; entries
    /// outside the pattern (and between unmarked columns) are zero.
    pub fn recover(&self, products: &DMatrix<f64>, out: &mut DMatrix<f64>) {
        assert_eq!(products.shape(), (self.dim, self.groups.len()));
        assert_eq!(out.shape(), (self.dim, self.dim));
        out.fill(0.0);
        for r in &self.reads {
            let value = match r.from.as_slice() {
                [(g, row)] => products[(*row, *g)],
                [(g1, r1), (g2, r2)] => 0.5 * (products[(*r1, *g1)] + products[(*r2, *g2)]),
                _ => unreachable!("an entry is read from one or two sides"),
            };
            out[(r.i, r.j)] = value;
            out[(r.j, r.i)] = value;
        }
    }
}

/// Hessian of `f` at `z` from its group products: per group, the rows it is read at in
/// tiles of [`TILE`], one [`HyperDualSVec64`]`<1, TILE>` pass each (ε₁ the group's seed, ε₂
/// the tile's rows).
pub fn grouped_hessian<F: ScalarFunction>(
    f: &F,
    z: &[f64],
    groups: &SymmetricGroups,
) -> DMatrix<f64> {
    let n = f.dim();
    assert_eq!(
        z.len(),
        n,
        "grouped_hessian: z has length {} but dim is {n}",
        z.len()
    );
    assert_eq!(
        groups.dim, n,
        "grouped_hessian: groups of another dimension"
    );
    let mut products = DMatrix::zeros(n, groups.groups.len());
    let mut zd: Vec<HyperDualSVec64<1, TILE>> =
        z.iter().map(|&x| HyperDualSVec64::from_re(x)).collect();
    for (g, members) in groups.groups.iter().enumerate() {
        for tile in groups.rows[g].chunks(TILE) {
            for (d, &x) in zd.iter_mut().zip(z) {
                *d = HyperDualSVec64::from_re(x);
            }
            for &j in members {
                zd[j] = zd[j].derivative1(0);
            }
            for (k, &row) in tile.iter().enumerate() {
                zd[row] = zd[row].derivative2(k);
            }
            let y = f.eval(&zd);
            if let Some(block) = &y.eps1eps2.0 {
                for (k, &row) in tile.iter().enumerate() {
                    products[(row, g)] = block[(0, k)];
                }
            }
        }
    }
    let mut out = DMatrix::zeros(n, n);
    groups.recover(&products, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::Scalar;
    use crate::autodiff::gradient_hessian;

    /// An arrow-and-band function like a state-tracking cost: Σ_i h (a_i + b_i)² sin(a_i b_i)
    /// over z = [a; b; h] (a pair per i, all coupled with h) plus a dense 3-input corner.
    struct Arrow(usize);
    impl ScalarFunction for Arrow {
        fn dim(&self) -> usize {
            2 * self.0 + 1
        }
        fn eval<D: Scalar>(&self, z: &[D]) -> D {
            let n = self.0;
            let h = z[2 * n];
            let mut s = z[0] * z[1] * z[2];
            for i in 0..n {
                let (a, b) = (z[i], z[n + i]);
                s += h * (a + b) * (a + b) * (a * b).sin();
            }
            s
        }
    }

    fn pattern(f: &Arrow, z: &[f64]) -> Vec<bool> {
        let h = gradient_hessian(f, z).2;
        h.transpose().iter().map(|v| *v != 0.0).collect()
    }

    #[test]
    fn grouped_hessian_equals_the_dense_one_in_fewer_passes() {
        let f = Arrow(9);
        let n = f.dim();
        let z: Vec<f64> = (0..n).map(|k| 0.3 + 0.1 * k as f64).collect();
        let dense = gradient_hessian(&f, &z).2;
        let groups = SymmetricGroups::new(n, &pattern(&f, &z), None);
        assert!(
            groups.groups().len() <= 6,
            "{} groups",
            groups.groups().len()
        );
        let grouped = grouped_hessian(&f, &z, &groups);
        for (a, b) in grouped.iter().zip(dense.iter()) {
            assert!(
                (a - b).abs() <= 1e-13 * (1.0 + b.abs()),
                "{grouped} vs {dense}"
            );
        }
        // Without h the remaining columns recover every entry between them.
        let mut free = vec![true; n];
        free[n - 1] = false;
        let groups = SymmetricGroups::new(n, &pattern(&f, &z), Some(&free));
        let grouped = grouped_hessian(&f, &z, &groups);
        for i in 0..n {
            for j in 0..n {
                let expected = if i == n - 1 || j == n - 1 {
                    0.0
                } else {
                    dense[(i, j)]
                };
                assert!((grouped[(i, j)] - expected).abs() <= 1e-13 * (1.0 + expected.abs()));
            }
        }
    }

    #[test]
    fn a_dense_pattern_takes_one_column_per_group() {
        let n = 5;
        let groups = SymmetricGroups::new(n, &vec![true; n * n], None);
        assert_eq!(groups.groups().len(), n);
        assert!(!groups.compresses());
    }
}
