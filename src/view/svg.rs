//! A strip as SVG: N evenly spaced poses, an orthographic view from the side (looking along
//! +y: world x to the right, z up), either side by side, each over its own piece of terrain
//! ([`StripLayout::Panels`]), or at their true world x over one terrain
//! ([`StripLayout::World`]).

use std::fmt::Write;

use super::{Drawing, Frame, Motion, Scene, rotation_of, xml_escape};

/// Height of the caption band naming the motion's verdict, pixels.
const CAPTION_H: f64 = 20.0;

/// Height of the band of time labels below the poses, pixels.
const LABEL_H: f64 = 22.0;

/// Widest a world-frame strip is drawn, pixels (a long motion is drawn smaller).
const MAX_WORLD_WIDTH: f64 = 2400.0;

/// Where a strip puts its poses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StripLayout {
    /// Side by side, each pose centred in a panel of its own over its own piece of terrain.
    #[default]
    Panels,
    /// In one world frame: each pose at its true x over one continuous terrain, earlier
    /// poses lighter, so that forward progress shows.
    World,
}

/// The frame nearest each of `n` evenly spaced times of `frames` (first and last included).
pub fn strip_frames(frames: &[Frame], n: usize) -> Vec<&Frame> {
    let (Some(first), Some(last)) = (frames.first(), frames.last()) else {
        return Vec::new();
    };
    (0..n)
        .map(|i| {
            let t = if n > 1 {
                first.time + (last.time - first.time) * i as f64 / (n - 1) as f64
            } else {
                first.time
            };
            frames
                .iter()
                .min_by(|a, b| (a.time - t).abs().total_cmp(&(b.time - t).abs()))
                .unwrap_or(first)
        })
        .collect()
}

/// Convex hull (monotone chain) of 2D points, counter-clockwise.
fn hull(mut points: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    points.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut lower: Vec<[f64; 2]> = Vec::new();
    for &p in &points {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<[f64; 2]> = Vec::new();
    for &p in points.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0.0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// One pose's parts as (depth y, colour, hull in world x–z).
fn silhouettes(drawing: &Drawing, frame: &Frame) -> Vec<(f64, [f32; 3], Vec<[f64; 2]>)> {
    let mut out = Vec::new();
    for part in &drawing.body.parts {
        let place = |link: usize| {
            let (p, q) = &frame.links[link];
            (*p, rotation_of(q))
        };
        let (near, far) = (
            place(part.link),
            part.slide
                .map(|(link, first)| (place(link), first as usize)),
        );
        let world = |(i, v): (usize, &[f64; 3])| {
            let (p, r) = match far {
                Some((far, first)) if i >= first => far,
                _ => near,
            };
            [
                p[0] + r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
                p[1] + r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
                p[2] + r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
            ]
        };
        let points: Vec<[f64; 3]> = part.vertices.iter().enumerate().map(world).collect();
        let depth = points.iter().map(|v| v[1]).sum::<f64>() / points.len().max(1) as f64;
        let outline = hull(points.iter().map(|v| [v[0], v[2]]).collect());
        if outline.iter().flatten().all(|v| v.is_finite()) {
            out.push((depth, part.color, outline));
        }
    }
    // Far (large y) first, near last.
    out.sort_by(|a, b| b.0.total_cmp(&a.0));
    out
}

fn colour(c: [f32; 3], shade: f32) -> String {
    let to = |v: f32| ((v * shade).clamp(0.0, 1.0) * 255.0).round() as u8;
    format!("#{:02x}{:02x}{:02x}", to(c[0]), to(c[1]), to(c[2]))
}

/// The strip of `n` poses of the first motion of `drawing` (`motion`, whose legend the caption
/// above the poses gives: a plan's verdict, in amber or red when it is not solved) as an SVG
/// document, laid out as `layout` says.
pub fn strip_svg(
    scene: &Scene,
    drawing: &Drawing,
    motion: &Motion,
    n: usize,
    layout: StripLayout,
) -> String {
    let frames = drawing.frames.first().map_or(&[][..], Vec::as_slice);
    let poses = strip_frames(frames, n.max(1));
    // Each pose's x–z box, and one panel width for all.
    let boxes: Vec<[f64; 4]> = poses
        .iter()
        .map(|f| {
            let s = silhouettes(drawing, f);
            let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
            for p in s.iter().flat_map(|x| &x.2) {
                b = [
                    b[0].min(p[0]),
                    b[1].min(p[1]),
                    b[2].max(p[0]),
                    b[3].max(p[1]),
                ];
            }
            for c in &f.contacts {
                b = [
                    b[0].min(c[0]),
                    b[1].min(c[2]),
                    b[2].max(c[0]),
                    b[3].max(c[2]),
                ];
            }
            b
        })
        .collect();
    let margin = 0.15 * drawing.size;
    if layout == StripLayout::World {
        return world_svg(scene, drawing, motion, &poses, &boxes, margin);
    }
    let width = pose_width(&boxes, drawing, margin);
    let mut z_lo = boxes.iter().map(|b| b[1]).fold(f64::MAX, f64::min);
    let z_hi = boxes.iter().map(|b| b[3]).fold(f64::MIN, f64::max) + margin;
    for (frame, b) in poses.iter().zip(&boxes) {
        let centre = (b[0] + b[2]) / 2.0;
        for i in 0..=20 {
            let x = centre - width / 2.0 + width * f64::from(i) / 20.0;
            z_lo = z_lo.min(scene.terrain.height_at(x, section_y(frame)));
        }
    }
    let z_lo = z_lo - margin;
    let px = 220.0 / width.max(1e-12);
    let (panel_w, panel_h) = (width * px, (z_hi - z_lo) * px);
    let total_w = panel_w * poses.len() as f64;
    let mut svg = svg_head(scene, motion, poses.len(), total_w, panel_h);
    for (i, (frame, b)) in poses.iter().zip(&boxes).enumerate() {
        let centre = (b[0] + b[2]) / 2.0;
        let x_left = centre - width / 2.0;
        let ox = panel_w * i as f64;
        let sx = |x: f64| ox + (x - x_left) * px;
        let sz = |z: f64| (z_hi - z) * px;
        let _ = writeln!(svg, r#"<g class="pose" data-time="{}">"#, frame.time);
        // Terrain: the profile through the pose's contacts filled down to the panel's bottom.
        let mut ground = format!("M{:.1},{:.1}", sx(x_left), sz(z_lo));
        let y = section_y(frame);
        for j in 0..=60 {
            let x = x_left + width * f64::from(j) / 60.0;
            let _ = write!(
                ground,
                " L{:.1},{:.1}",
                sx(x),
                sz(scene.terrain.height_at(x, y))
            );
        }
        let _ = write!(ground, " L{:.1},{:.1} Z", sx(x_left + width), sz(z_lo));
        let _ = writeln!(
            svg,
            r##"<path d="{ground}" fill="#d9d4c7" stroke="#8a8374" stroke-width="1"/>"##
        );
        pose_shapes(&mut svg, drawing, frame, sx, sz);
        let _ = writeln!(
            svg,
            r##"<text x="{:.1}" y="{:.1}" text-anchor="middle" fill="#333">t = {:.4} {}</text></g>"##,
            ox + panel_w / 2.0,
            panel_h + 16.0,
            frame.time,
            xml_escape(&scene.time_unit)
        );
        if i > 0 {
            let _ = writeln!(
                svg,
                r##"<line x1="{ox:.1}" y1="0" x2="{ox:.1}" y2="{panel_h:.1}" stroke="#bbb"/>"##
            );
        }
    }
    svg.push_str("</g></svg>\n");
    svg
}

/// One pose's part silhouettes and contact points, placed by `sx` (world x to pixels) and
/// `sz` (world z to pixels).
fn pose_shapes(
    svg: &mut String,
    drawing: &Drawing,
    frame: &Frame,
    sx: impl Fn(f64) -> f64,
    sz: impl Fn(f64) -> f64,
) {
    for (_, c, outline) in silhouettes(drawing, frame) {
        let points: Vec<String> = outline
            .iter()
            .map(|p| format!("{:.1},{:.1}", sx(p[0]), sz(p[1])))
            .collect();
        let _ = writeln!(
            svg,
            r#"<polygon points="{}" fill="{}" stroke="{}" stroke-width="0.8" stroke-linejoin="round"/>"#,
            points.join(" "),
            colour(c, 1.0),
            colour(c, 0.55)
        );
    }
    for c in &frame.contacts {
        let _ = writeln!(
            svg,
            r##"<circle cx="{:.1}" cy="{:.1}" r="2.5" fill="#c0392b"/>"##,
            sx(c[0]),
            sz(c[2])
        );
    }
}

/// The SVG's opening: its mark, size (`panel_h` high for the poses, plus the caption and the
/// labels), title and the caption naming the verdict; the poses follow inside a group moved
/// below the caption.
fn svg_head(scene: &Scene, motion: &Motion, poses: usize, width: f64, panel_h: f64) -> String {
    let height = panel_h + LABEL_H + CAPTION_H;
    let mut svg = format!("{}\n", super::SVG_MARK);
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.1} {height:.1}" font-family="sans-serif" font-size="13">"#
    );
    let _ = writeln!(
        svg,
        r##"<rect width="100%" height="100%" fill="#ffffff"/><title>{}: {poses} poses</title>"##,
        xml_escape(&scene.title),
    );
    let _ = writeln!(
        svg,
        r#"<text class="verdict" data-standing="{}" x="6" y="15" fill="{}">{}</text><g transform="translate(0 {CAPTION_H})">"#,
        motion.standing.name(),
        motion.standing.colour().unwrap_or("#333"),
        xml_escape(&motion.detail)
    );
    svg
}

/// The width one pose takes: its widest box (at least half the robot's size) and a margin
/// either side.
fn pose_width(boxes: &[[f64; 4]], drawing: &Drawing, margin: f64) -> f64 {
    boxes
        .iter()
        .map(|b| b[2] - b[0])
        .fold(0.0, f64::max)
        .max(drawing.size * 0.5)
        + 2.0 * margin
}

/// The world-frame strip: every pose at its own x over one terrain profile spanning them
/// all (`boxes`: each pose's x–z box), opacity rising from the first pose to the last; one
/// line below the ground gives the poses' times (overlapping poses leave no room for a label
/// each). At least wide enough for the caption, the terrain widened to fill it.
fn world_svg(
    scene: &Scene,
    drawing: &Drawing,
    motion: &Motion,
    poses: &[&Frame],
    boxes: &[[f64; 4]],
    margin: f64,
) -> String {
    let pose_width = pose_width(boxes, drawing, margin);
    let x_lo = boxes.iter().map(|b| b[0]).fold(f64::MAX, f64::min) - margin;
    let x_hi = boxes.iter().map(|b| b[2]).fold(f64::MIN, f64::max) + margin;
    let (x_lo, x_hi) = if x_lo.is_finite() && x_hi.is_finite() && x_hi > x_lo {
        (x_lo, x_hi)
    } else {
        (-drawing.size, drawing.size)
    };
    let px = (220.0 / pose_width.max(1e-12)).min(MAX_WORLD_WIDTH / (x_hi - x_lo));
    // Room for the caption and the times: about 7 px a character at 13 px.
    let min_w = (7.0 * motion.detail.chars().count().max(40) as f64 + 12.0).min(MAX_WORLD_WIDTH);
    let widen = ((min_w / px - (x_hi - x_lo)) / 2.0).max(0.0);
    let (x_lo, x_hi) = (x_lo - widen, x_hi + widen);
    // The section through the poses' contacts, on average.
    let y = poses.iter().map(|f| section_y(f)).sum::<f64>() / poses.len().max(1) as f64;
    let (xs, zs) = super::terrain_profile(&scene.terrain, x_lo, x_hi, y);
    let z_lo = boxes
        .iter()
        .map(|b| b[1])
        .chain(zs.iter().copied())
        .fold(f64::MAX, f64::min)
        - margin;
    let z_hi = boxes.iter().map(|b| b[3]).fold(f64::MIN, f64::max) + margin;
    let (total_w, panel_h) = ((x_hi - x_lo) * px, (z_hi - z_lo) * px);
    let sx = |x: f64| (x - x_lo) * px;
    let sz = |z: f64| (z_hi - z) * px;
    let mut svg = svg_head(scene, motion, poses.len(), total_w, panel_h);
    let mut ground = format!("M{:.1},{:.1}", sx(x_lo), sz(z_lo));
    for (x, z) in xs.iter().zip(&zs) {
        let _ = write!(ground, " L{:.1},{:.1}", sx(*x), sz(*z));
    }
    let _ = write!(ground, " L{:.1},{:.1} Z", sx(x_hi), sz(z_lo));
    let _ = writeln!(
        svg,
        r##"<path class="terrain" d="{ground}" fill="#d9d4c7" stroke="#8a8374" stroke-width="1"/>"##
    );
    let last = poses.len().saturating_sub(1).max(1) as f64;
    for (i, frame) in poses.iter().enumerate() {
        let opacity = if poses.len() > 1 {
            0.3 + 0.7 * i as f64 / last
        } else {
            1.0
        };
        let _ = writeln!(
            svg,
            r#"<g class="pose" data-time="{}" opacity="{opacity:.2}">"#,
            frame.time
        );
        pose_shapes(&mut svg, drawing, frame, sx, sz);
        svg.push_str("</g>\n");
    }
    let (first, last) = (
        poses.first().map_or(0.0, |f| f.time),
        poses.last().map_or(0.0, |f| f.time),
    );
    let _ = writeln!(
        svg,
        r##"<text class="times" x="6" y="{:.1}" fill="#333">{} poses, t = {:.4} to {:.4} {}, earlier ones lighter</text>"##,
        panel_h + 16.0,
        poses.len(),
        first,
        last,
        xml_escape(&scene.time_unit)
    );
    svg.push_str("</g></svg>\n");
    svg
}

/// The world y of the terrain section a pose is drawn over: the mean y of its contact points
/// (0 without contacts), so that a robot on a slope falling along y stands on its ground.
fn section_y(frame: &super::Frame) -> f64 {
    if frame.contacts.is_empty() {
        return 0.0;
    }
    frame.contacts.iter().map(|p| p[1]).sum::<f64>() / frame.contacts.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_of_a_square_with_an_inner_point() {
        let h = hull(vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [0.5, 0.5],
        ]);
        assert_eq!(h.len(), 4);
        assert!(!h.contains(&[0.5, 0.5]));
    }
}
