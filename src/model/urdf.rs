//! URDF → [`Model`]: urdf-rs for the standard elements, a roxmltree pass for Drake's
//! extensions. The only file that imports `urdf_rs`.

use super::{BaseType, Model, ModelError};

/// Parses, repairs, checks and converts a URDF document.
pub(crate) fn load(xml: &str, origin: &str, base: BaseType) -> Result<Model, ModelError> {
    let _ = (xml, origin, base);
    unimplemented!("urdf::load")
}
