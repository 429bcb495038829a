//! Notebook display (`_repr_html_`) of a solution or simulation: a summary table and the
//! motion viewer's self-contained page (what `animation.html` holds) inline, in an iframe.

use serde_json::Value;

use vito::files::names::xml_escape as escape;
use vito::files::trajectory_csv::Trajectory;
use vito::problem::LoadedProblem;

/// The summary table (`rows`: label, value) and the motion page of `trajectory` below it;
/// when the page cannot be drawn, the reason in its place.
pub(crate) fn result_html(
    kind: &str,
    problem: &LoadedProblem,
    rows: &[(&str, String)],
    trajectory: &Trajectory<'_>,
    summary: &Value,
) -> String {
    let mut html = format!(
        "<div class=\"vito-result\"><table><caption style=\"text-align:left\"><b>vito {}</b> \
         {}</caption>",
        escape(kind),
        escape(&problem.spec.name)
    );
    for (label, value) in rows {
        html.push_str(&format!(
            "<tr><th style=\"text-align:left\">{}</th><td style=\"text-align:left\">{}</td></tr>",
            escape(label),
            escape(value)
        ));
    }
    html.push_str("</table>");
    match vito::view::animation_page(problem, trajectory, summary) {
        Ok((page, _)) => html.push_str(&format!(
            "<iframe srcdoc=\"{}\" style=\"width:100%;height:560px;border:1px solid #ddd\" \
             sandbox=\"allow-scripts\"></iframe>",
            escape(&page)
        )),
        Err(e) => html.push_str(&format!(
            "<p>(no motion page: {})</p>",
            escape(&e.to_string())
        )),
    }
    html.push_str("</div>");
    html
}
