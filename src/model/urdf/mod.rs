//! URDF → [`Model`]: urdf-rs reads the standard elements, a roxmltree pass reads Drake's
//! extensions. The only module that imports `urdf_rs`: `repair` mends the text, `extensions`
//! reads Drake's elements, `inertia` checks and lumps masses, `build` makes the [`Model`].
//!
//! Read: links (`<inertial>`; mass 0 is a massless frame; `<collision>` spheres of any
//! radius as contacts; other collision shapes listed as ignored), joints of type fixed, revolute, continuous and prismatic (origin,
//! axis, `<limit>` lower/upper/effort, `<dynamics damping>`, `<mimic>`: no coordinate of its
//! own, θ = multiplier·q_leader + offset, its `<limit>` applied to the leader's coordinate,
//! with a warning when it narrows it), `<transmission>` joints (inputs), and Drake's
//! `<force_element>` (`<torsional_spring>`, `<prismatic_spring>`) and `<loop_joint>`.
//! Inertias are checked on the rigid bodies after fixed children are lumped in, and every
//! problem of masses and mimics is reported at once, by line and element.
//!
//! Repaired before parsing, each listed in [`Model::warnings`] (the original files of the
//! paper's robots need them): a `<limit>` without `velocity` or `effort` (both then mean "no
//! limit"), `pi`-expressions such as `-pi/4` in `<limit>`, commas in `xyz`/`rpy`, a one-value
//! mesh `scale`, capitalised joint types, and stray `/` text.
//!
//! A `<limit>` value of magnitude [`values::NO_LIMIT`] (1e19, Ipopt's infinity) or more is no
//! limit, as `inf` is: portable URDFs write it where urdfdom (ROS's and Pinocchio's reader)
//! needs a finite number.
//!
//! Visual and collision shapes are kept for drawing only (`geometry`: checked, never read
//! as mechanics; mesh files are not opened here).
//!
//! Limitations (ignored): collision boxes, cylinders and meshes,
//! `velocity` limits, `friction` in `<dynamics>`, `<calibration>`,
//! `<safety_controller>`, `mechanicalReduction` (must be 1), `<gazebo>`, Drake `<frame>`
//! (reported as a warning), collision groups.

mod bodies;

pub use bodies::SPHERE_HINT;
mod build;
mod extensions;
mod geometry;
mod inertia;
mod joint_elements;
mod limits;
mod parts;
mod repair;
mod values;

use std::path::Path;

use roxmltree::Document;

use super::{BaseType, Model, ModelError};

impl Model {
    /// Loads a URDF file (Drake extensions included) with the given base.
    ///
    /// Repairs that are unambiguous (a `<limit>` without `velocity` or `effort`, which then
    /// mean "no limit") are made and listed in [`Model::warnings`].
    pub fn from_urdf_file(path: &Path, base: BaseType) -> Result<Model, ModelError> {
        let xml = crate::files::input::read_regular_text(path, crate::files::input::MAX_URDF_BYTES)
            .map_err(|source| ModelError::Io {
                path: path.to_path_buf(),
                source,
            })?;
        load(&xml, &path.display().to_string(), base)
    }

    /// Loads a URDF from a string; see [`Model::from_urdf_file`].
    ///
    /// # Example
    /// ```
    /// use vito::model::{BaseType, Model, mass_matrix, sample};
    /// let model = Model::from_urdf_str(&sample::pendulum(), BaseType::Fixed).unwrap();
    /// assert_eq!(model.coordinate_names(), ["joint1"]);
    /// // A uniform 1 kg, 1 m rod about its end: m l²/3.
    /// assert!((mass_matrix(&model, &[0.4])[(0, 0)] - 1.0 / 3.0).abs() < 1e-14);
    /// ```
    pub fn from_urdf_str(xml: &str, base: BaseType) -> Result<Model, ModelError> {
        load(xml, "<string>", base)
    }

    /// Loads a URDF from a string that messages call `origin` (its file's path).
    pub fn from_urdf_named(xml: &str, origin: &str, base: BaseType) -> Result<Model, ModelError> {
        load(xml, origin, base)
    }
}

/// Parses, repairs, checks and converts a URDF document.
pub(crate) fn load(xml: &str, origin: &str, base: BaseType) -> Result<Model, ModelError> {
    limits::check_nesting(xml, origin)?;
    let mut warnings = Vec::new();
    let repaired = repair::repair(xml, origin, &mut warnings)?;
    let doc = Document::parse(&repaired).map_err(|e| xml_error(origin, e))?;
    limits::check_counts(&doc, origin)?;
    let extensions = extensions::read_extensions(&doc, &mut warnings)?;
    let mut robot = urdf_rs::read_from_string(&repaired).map_err(|e| ModelError::Urdf {
        origin: origin.to_string(),
        message: e.to_string(),
    })?;
    values::open_limits(&mut robot);
    values::check_values(&robot, &extensions)?;
    let geometry = geometry::read(&robot)?;
    let mut model = build::build(&robot, &extensions, base, origin, warnings)?;
    limits::check_coordinates(&model, &robot, origin)?;
    // The first shapes listed under each name, looked up by name (a scan per link was
    // quadratic in the links).
    let mut by_name = std::collections::HashMap::with_capacity(geometry.len());
    for (name, shapes) in &geometry {
        by_name.entry(name.as_str()).or_insert(shapes);
    }
    model.geometry = model
        .link_names
        .iter()
        .map(|name| {
            by_name
                .get(name.as_str())
                .map(|&g| g.clone())
                .unwrap_or_default()
        })
        .collect();
    Ok(model)
}

/// The line numbers of a text's byte offsets, by binary search over its line ends: built
/// once per document (roxmltree's `text_pos_at` scans from the start at each call, which
/// made a line per element quadratic in the document: 14 s for 10,000 links).
pub(super) struct Lines(Vec<usize>);

impl Lines {
    /// The line ends of `text`.
    pub(super) fn new(text: &str) -> Self {
        Lines(text.match_indices('\n').map(|(i, _)| i).collect())
    }

    /// The line (from 1) holding byte `pos`, as roxmltree counts (a URDF is read only up
    /// to 64 MiB, so the line fits).
    pub(super) fn row(&self, pos: usize) -> u32 {
        (self.0.partition_point(|&end| end < pos) + 1) as u32
    }
}

pub(super) fn xml_error(origin: &str, e: roxmltree::Error) -> ModelError {
    ModelError::Xml {
        origin: origin.to_string(),
        message: e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The line of every node's start is the line roxmltree counts.
    #[test]
    fn lines_agree_with_the_parser() {
        let xml =
            "<robot>\n<link name=\"a\"/>\n\n  <joint>\n<x/></joint><!-- c\n -->\n<y/></robot>\n";
        let doc = Document::parse(xml).unwrap();
        let lines = Lines::new(xml);
        for node in doc.descendants() {
            let pos = node.range().start;
            assert_eq!(lines.row(pos), doc.text_pos_at(pos).row, "{node:?}");
        }
        assert_eq!(lines.row(0), 1);
        assert_eq!(lines.row(xml.len()), 8);
    }
}
