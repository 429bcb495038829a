//! Safe wrapper over Debian's system Ipopt (C interface `IpStdCInterface.h`, bindings by
//! bindgen in `build.rs`). The only module with `unsafe`.

mod nlp;

pub use nlp::{IterationInfo, Nlp};
