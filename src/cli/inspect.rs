//! `vito inspect`: a robot's summary from a URDF.

use std::path::Path;

use vito::model::BaseType;

use super::error::CliError;

/// `base` as resolved, with the reason `--base auto` gave (none for a base asked for).
pub(super) fn inspect(
    urdf: &Path,
    (base, reason): (BaseType, Option<String>),
    json: bool,
) -> Result<u8, CliError> {
    let model = vito::model::Model::from_urdf_file(urdf, base)
        .map_err(|e| CliError::Input(vito::model::describe(urdf, &e)))?;
    let mut inspection = vito::model::inspect(&model);
    inspection.base_reason = reason;
    if json {
        let text = serde_json::to_string_pretty(&inspection)
            .map_err(|e| CliError::Internal(e.to_string()))?;
        out!("{text}");
    } else {
        out!("{inspection}");
    }
    Ok(0)
}
