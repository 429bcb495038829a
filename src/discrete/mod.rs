//! Discrete mechanics: the midpoint discrete Lagrangian (second order, the paper's method), its
//! fourth- and sixth-order Galerkin relatives, and the first-order semi-implicit Euler time
//! stepping it is compared against, with the forward step (no contact) that exercises them.
//!
//! Where things are:
//! - `mechanics`: the [`Mechanics`] trait, the physics a robot offers (Ld, Fd, momentum,
//!   contact positions, loop closures, names, limits); `derivatives`: the
//!   [`MechanicsDerivatives`] trait, its derivative fast paths with forward-AD defaults;
//!   `model_mechanics`: both for a URDF model.
//! - `midpoint`: the midpoint state, Ld, Fd, slot derivatives and Legendre transforms of a
//!   model; `midpoint_derivatives`: its adjoint gradient, Hessian and third order of Ld.
//! - `del`: the DEL equations of any mechanics: the pieces the NLP places on its rows, and the
//!   knot residual and its Jacobian in q_{k+1} for a forward step.
//! - `galerkin`: the Galerkin variational integrators of degree s (order 2s; s = 1 is the
//!   midpoint rule): nodes, quadrature, the interval action and discrete forces;
//!   `galerkin_interval`: an interval's interior points solved, its end momenta and their
//!   derivatives, for forward steps.
//! - `euler`: the semi-implicit Euler residual; `loops`: loop closures; `step`: forward steps.
//!
//! Sign convention shared by both integrators (so the NLP can swap them): every residual is a
//! momentum balance in impulse units (N·s, or N·m·s for angles), *momentum before − momentum
//! after + impulses*, so that contact impulses enter as `+ J(q_{k+1})ᵀ λ_k` and loop-closure
//! impulses as `+ G(q_{k+1})ᵀ ν_k`, with G = ∂ loop_residual / ∂q.
//!
//! Every function of configurations is generic over [`crate::autodiff::Scalar`]; the structs
//! ([`MidpointSegment`], [`DiscreteForce`], [`InitialMomentum`], [`EulerKnotResidual`],
//! [`LoopClosure`], [`MidpointKnotResidual`]) wrap them as [`crate::autodiff`] functions of one
//! flat input vector, whose layout each documents.

mod del;
mod derivatives;
mod euler;
mod galerkin;
mod galerkin_interval;
mod loops;
mod mechanics;
mod midpoint;
mod midpoint_derivatives;
mod model_mechanics;
mod step;

pub use del::*;
pub use derivatives::*;
pub use euler::*;
pub use galerkin::*;
pub use galerkin_interval::*;
pub use loops::*;
pub use mechanics::Mechanics;
pub use midpoint::*;
pub use midpoint_derivatives::*;
pub use model_mechanics::{ContactSphere, ModelMechanics};
pub use step::*;

/// Which discrete mechanics the dynamics constraints use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Integrator {
    /// Midpoint discrete Lagrangian Ld = h·L((qa+qb)/2, (qb−qa)/h): second order, the paper's.
    #[default]
    Midpoint,
    /// First-order semi-implicit Euler time stepping (Posa et al. 2014, eq. 1 of the paper).
    Euler,
    /// Galerkin variational integrator of degree 2 (one interior point per interval, two
    /// Gauss points): fourth order ([`GalerkinRule`]).
    Galerkin4,
    /// Galerkin variational integrator of degree 3 (two interior points per interval, three
    /// Gauss points): sixth order.
    Galerkin6,
}

impl Integrator {
    /// Every integrator, in the order messages list them.
    pub const ALL: [Integrator; 4] = [
        Integrator::Midpoint,
        Integrator::Euler,
        Integrator::Galerkin4,
        Integrator::Galerkin6,
    ];

    /// The integrator's name, as a problem file (`[solver] integrator`), the command line
    /// (`--integrator`), the Python package and `summary.json` spell it.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::Midpoint => "midpoint",
            Integrator::Euler => "euler",
            Integrator::Galerkin4 => "galerkin4",
            Integrator::Galerkin6 => "galerkin6",
        }
    }

    /// The order of accuracy on smooth motion: 1 (Euler), 2 (midpoint), 4 or 6 (Galerkin).
    pub fn order(self) -> usize {
        match self {
            Integrator::Euler => 1,
            Integrator::Midpoint => 2,
            Integrator::Galerkin4 => 4,
            Integrator::Galerkin6 => 6,
        }
    }

    /// The degree s of the Galerkin member with interior points (2 or 3), or `None` for the
    /// midpoint rule (the s = 1 member, which has none and its own faster derivatives) and
    /// Euler.
    pub fn galerkin_degree(self) -> Option<usize> {
        match self {
            Integrator::Midpoint | Integrator::Euler => None,
            Integrator::Galerkin4 => Some(2),
            Integrator::Galerkin6 => Some(3),
        }
    }

    /// The Galerkin member with interior points ([`Integrator::galerkin_degree`]).
    pub fn galerkin_rule(self) -> Option<GalerkinRule> {
        self.galerkin_degree().and_then(GalerkinRule::of_degree)
    }
}

impl std::str::FromStr for Integrator {
    type Err = String;

    /// The integrator named `name` ([`Integrator::name`]); the error lists the names.
    fn from_str(name: &str) -> Result<Self, String> {
        Integrator::ALL
            .into_iter()
            .find(|i| i.name() == name)
            .ok_or_else(|| {
                let names: Vec<String> = Integrator::ALL.map(|i| format!("{:?}", i.name())).into();
                format!(
                    "`{name}` is not an integrator: give one of {}",
                    names.join(", ")
                )
            })
    }
}

#[cfg(test)]
mod integrator_tests {
    use super::Integrator;

    /// Every integrator parses back from its name; another name is an error listing them.
    #[test]
    fn names_parse_back_and_unknown_names_list_them() {
        for i in Integrator::ALL {
            assert_eq!(i.name().parse::<Integrator>(), Ok(i));
        }
        assert_eq!(
            Integrator::ALL.map(Integrator::name),
            ["midpoint", "euler", "galerkin4", "galerkin6"]
        );
        assert_eq!(Integrator::ALL.map(Integrator::order), [2, 1, 4, 6]);
        for i in Integrator::ALL {
            let rule = i.galerkin_rule();
            assert_eq!(
                rule.map(|r| 2 * r.degree()),
                i.galerkin_degree().map(|_| i.order())
            );
        }
        let e = "rk4".parse::<Integrator>().unwrap_err();
        assert_eq!(
            e,
            "`rk4` is not an integrator: give one of \"midpoint\", \"euler\", \"galerkin4\", \"galerkin6\""
        );
    }
}
