//! The variational contact NLP: variable layout, constraint blocks, costs, sparse assembly.

mod solution;

pub use solution::{NlpSize, Solution};
