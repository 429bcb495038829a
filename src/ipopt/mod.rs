//! Safe wrapper over Debian's system Ipopt (C interface `IpStdCInterface.h`, bindings by
//! bindgen in `build.rs`). The only module with `unsafe`.

mod nlp;
mod sys;
mod status;

pub use nlp::{IterationInfo, Nlp};
pub use status::Status;
