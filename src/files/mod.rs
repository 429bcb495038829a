//! The files a user names and the text vito writes about them: reading them safely
//! ([`input`]), naming one from another's directory ([`paths`]), the trajectory CSV format
//! ([`trajectory_csv`]), and how messages list names ([`names`]).

pub mod input;
pub mod names;
pub mod paths;
pub mod trajectory_csv;
