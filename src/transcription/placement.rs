//! Block placement: every kind places its own blocks (its `place` method, in its file under
//! `blocks`), stage by stage over the NLP's skeleton ([`super::blocks::Stage`]).

use super::Transcription;
use super::blocks::Placement;
use crate::discrete::MechanicsDerivatives;

impl<M: MechanicsDerivatives> Transcription<M> {
    pub(super) fn place_blocks(&mut self) {
        let rolls = (0..self.layout.nc)
            .map(|i| self.mech.contact_rolls(i))
            .collect();
        let mut placement = Placement::new(
            &self.layout,
            &self.ctx,
            self.mech.has_discrete_force(),
            rolls,
        );
        placement.place_all();
        self.vector_blocks = placement.vector;
        self.gradient_blocks = placement.gradient;
        self.cost_blocks = placement.cost;
    }
}
