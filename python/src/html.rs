//! Notebook display (`_repr_html_`) of a solution or simulation: a summary table and the
//! motion viewer's self-contained page (what `animation.html` holds) inline, in an iframe.

use serde_json::Value;

use vito::files::trajectory_csv::Trajectory;
use vito::problem::LoadedProblem;

/// Escapes text for HTML content and attribute values.
pub(crate) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

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
