//! The files a user names and the text vito writes about them: reading them safely
//! ([`input`]), writing them atomically and never through a link ([`output`]), naming one from another's directory ([`paths`]), the trajectory CSV format
//! ([`trajectory_csv`]), and how messages list names ([`names`]).

pub mod input;
pub mod names;
pub mod output;
pub mod paths;
pub mod trajectory_csv;
