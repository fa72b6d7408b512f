//! Drawing a collected run: the room top-down above, one force-over-time panel per push test below.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use anyhow::{Context, anyhow};
use nalgebra::{Point2, Vector2};
use nudge_executive::{Question, Verdict};
use nudge_perception::grid::CellClass;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{ForceTrace, MapCollector, font};

/// Picture width (px).
const WIDTH: u32 = 1400;
/// Largest height of the room's drawing (px).
const MAP_MAX_HEIGHT: f64 = 760.0;
/// Height of one force panel (px); three panels to a row.
const PANEL_HEIGHT: u32 = 300;
const PANELS_PER_ROW: u32 = 3;
/// Space for the caption and the axes around the room (px).
const CAPTION: u32 = 40;
/// The caption's font size (px): its line fits the picture's width in the bundled monospaced font.
const CAPTION_SIZE: u32 = 14;
const X_AXIS: u32 = 40;
const Y_AXIS: u32 = 60;
const MARGIN: u32 = 15;

const TRACK: RGBColor = RGBColor(150, 20, 160);
const PATH: RGBColor = RGBColor(20, 160, 60);
const PRISM: RGBColor = RGBColor(230, 140, 20);
const TRUTH: RGBColor = RGBColor(120, 120, 120);
const GOAL: RGBColor = RGBColor(0, 170, 0);
const UNTESTED: RGBColor = RGBColor(230, 140, 20);
const VIEW: RGBColor = RGBColor(0, 140, 200);
/// Radius of the wedge drawn for a viewpoint's look-around (m): a marker, not the camera's range.
const VIEW_WEDGE: f64 = 0.8;

type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// Writes `run` as a PNG into `file` (opened at `path` before the run, so a bad path fails early):
/// the map, and below it a force panel per push test.
pub fn draw(run: &MapCollector, file: File, path: &Path) -> anyhow::Result<()> {
    let room = run.scenario.room.size;
    let scale = ((f64::from(WIDTH - Y_AXIS - 2 * MARGIN)) / room[0]).min(MAP_MAX_HEIGHT / room[1]);
    let map_height = (room[1] * scale).ceil() as u32 + CAPTION + X_AXIS + 2 * MARGIN;
    let rows = (run.tests.len() as u32).div_ceil(PANELS_PER_ROW);
    let height = map_height + rows * PANEL_HEIGHT;
    let mut buffer = vec![255u8; (WIDTH * height * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let (top, bottom) = root.split_vertically(map_height);
        let right = WIDTH - Y_AXIS - MARGIN - (room[0] * scale).ceil() as u32;
        draw_map(run, &top, right).map_err(plot_error)?;
        if rows > 0 {
            let panels = bottom.split_evenly((rows as usize, PANELS_PER_ROW as usize));
            for (i, (test, panel)) in run.tests.iter().zip(&panels).enumerate() {
                draw_forces(i + 1, test, panel, run).map_err(plot_error)?;
            }
        }
        root.present().map_err(plot_error)?;
    }
    let image = image::RgbImage::from_raw(WIDTH, height, buffer)
        .ok_or_else(|| anyhow!("picture buffer has the wrong size"))?;
    let mut out = BufWriter::new(file);
    image
        .write_to(&mut out, image::ImageFormat::Png)
        .map_err(anyhow::Error::from)
        .and_then(|()| Ok(out.flush()?))
        .with_context(|| format!("cannot write {}", path.display()))
}

fn plot_error<E: std::fmt::Display>(e: E) -> anyhow::Error {
    anyhow!("cannot draw the map: {e}")
}

type DrawResult =
    Result<(), DrawingAreaErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>>;

fn draw_map(run: &MapCollector, area: &Area<'_>, right: u32) -> DrawResult {
    let room = run.scenario.room.size;
    let text = font::available();
    let mut builder = ChartBuilder::on(area);
    builder
        .margin_top(MARGIN)
        .margin_bottom(MARGIN)
        .margin_left(MARGIN)
        .margin_right(right);
    if text {
        builder
            .caption(caption(run), ("sans-serif", CAPTION_SIZE))
            .x_label_area_size(X_AXIS)
            .y_label_area_size(Y_AXIS);
    } else {
        builder
            .margin_top(MARGIN + CAPTION)
            .margin_bottom(MARGIN + X_AXIS)
            .margin_left(MARGIN + Y_AXIS);
    }
    let mut chart = builder.build_cartesian_2d(0.0..room[0], 0.0..room[1])?;
    if text {
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("x (m)")
            .y_desc("y (m)")
            .draw()?;
    }
    // The obstacle-type grid (or plain floor until the runner reports one).
    if let Some(grid) = &run.grid {
        let r = grid.resolution;
        chart.draw_series(grid.classes.iter().enumerate().filter_map(|(i, &code)| {
            let class = CellClass::from_code(code)?;
            let (cx, cy) = (i % grid.width.max(1), i / grid.width.max(1));
            let x = grid.origin.x + cx as f64 * r;
            let y = grid.origin.y + cy as f64 * r;
            Some(Rectangle::new(
                [(x, y), (x + r, y + r)],
                cell_colour(class).filled(),
            ))
        }))?;
    }
    chart.draw_series(std::iter::once(Rectangle::new(
        [(0.0, 0.0), (room[0], room[1])],
        BLACK.stroke_width(2),
    )))?;
    // Ground truth, thin grey outlines: what the robot had to find.
    for object in &run.scenario.objects {
        if let Some(footprint) = object.footprint() {
            chart.draw_series(std::iter::once(closed(
                &footprint.polygon(),
                TRUTH.stroke_width(1),
            )))?;
        }
    }
    // What perception made of it.
    for prism in &run.prisms {
        let corners: Vec<(f64, f64)> = prism.footprint.iter().map(|p| (p.x, p.y)).collect();
        chart.draw_series(std::iter::once(Polygon::new(
            corners,
            PRISM.mix(0.35).filled(),
        )))?;
        chart.draw_series(std::iter::once(closed(
            &prism.footprint,
            PRISM.stroke_width(2),
        )))?;
        if text && let Some(c) = centroid(&prism.footprint) {
            chart.draw_series(std::iter::once(Text::new(
                prism.id.to_string(),
                (c.x, c.y),
                ("sans-serif", 14).into_font(),
            )))?;
        }
    }
    for (i, path) in run.paths.iter().enumerate() {
        let older = if i + 1 == run.paths.len() { 1.0 } else { 0.45 };
        chart.draw_series(std::iter::once(PathElement::new(
            path.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>(),
            PATH.mix(older).stroke_width(3),
        )))?;
    }
    chart.draw_series(std::iter::once(PathElement::new(
        run.track.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>(),
        TRACK.stroke_width(2),
    )))?;
    // The viewpoints chosen: where the robot stood and the span of its look-around.
    for (k, (question, view)) in run.views.iter().enumerate() {
        chart.draw_series(std::iter::once(PathElement::new(
            wedge(view.position, view.yaw, run.look_half_angle),
            VIEW.stroke_width(2),
        )))?;
        chart.draw_series(std::iter::once(Circle::new(
            (view.position.x, view.position.y),
            5,
            VIEW.filled(),
        )))?;
        if text {
            let what = match question {
                Question::PathAhead => "path ahead".to_string(),
                Question::Way => "a way".to_string(),
                Question::Push { target, .. } => format!("push {target}"),
            };
            chart.draw_series(std::iter::once(Text::new(
                format!("V{}: {what}", k + 1),
                (view.position.x + 0.08, view.position.y - 0.12),
                ("sans-serif", 14).into_font().color(&VIEW),
            )))?;
        }
    }
    let start = run.scenario.robot.start_position();
    let goal = &run.scenario.goal;
    let px = |m: f64| ((m * area.dim_in_pixel().0 as f64 / room[0]).round() as i32).max(3);
    chart.draw_series(std::iter::once(Circle::new(
        (start.x, start.y),
        px(run.scenario.robot.radius()),
        TRACK.stroke_width(2),
    )))?;
    chart.draw_series(std::iter::once(Circle::new(
        (goal.position[0], goal.position[1]),
        px(goal.tolerance),
        GOAL.filled(),
    )))?;
    for push in &run.pushes {
        let colour = verdict_colour(run.verdict_of(push.intent.target));
        let from = Point2::from(push.intent.stand.translation.vector);
        let d = push.intent.direction.into_inner();
        let to = from + d * push.intent.distance.max(0.3);
        chart.draw_series(arrow(from, to, colour))?;
        if text {
            let word = match run.verdict_of(push.intent.target) {
                Some(v) if v.is_movable() => "movable",
                Some(_) => "static",
                None => "untested",
            };
            chart.draw_series(std::iter::once(Text::new(
                format!("{} {word}, {:.1} N", push.intent.target, push.force.norm()),
                (to.x + 0.05, to.y + 0.05),
                ("sans-serif", 14).into_font().color(&colour),
            )))?;
        }
    }
    Ok(())
}

fn draw_forces(n: usize, test: &ForceTrace, area: &Area<'_>, run: &MapCollector) -> DrawResult {
    let area = area.margin(10, 10, 10, 10);
    // A test that reported no limit was the default robot's.
    let limit = test
        .limit
        .unwrap_or_else(|| nudge_robot_model::ForceModel::default().test_limit);
    let t0 = test.samples.first().map_or(0.0, |s| s.0);
    let duration = test.samples.last().map_or(1.0, |s| s.0 - t0).max(0.1);
    let peak = test.samples.iter().map(|s| s.1).fold(0.0, f64::max);
    let top = (limit * 1.25).max(peak * 1.1);
    let text = font::available();
    let mut builder = ChartBuilder::on(&area);
    if text {
        let verdict = match &test.verdict {
            Some(v) if v.is_movable() => "movable".to_string(),
            Some(_) => "static".to_string(),
            None => "no verdict yet".to_string(),
        };
        let object = test
            .object
            .map_or_else(|| "?".to_string(), |o| o.to_string());
        builder
            .caption(
                format!(
                    "push test {n}: {object} #{} -> {verdict}, peak {peak:.1} N",
                    test.attempt
                ),
                ("sans-serif", 15),
            )
            .x_label_area_size(30)
            .y_label_area_size(45);
    }
    let mut chart = builder.build_cartesian_2d(0.0..duration, 0.0..top)?;
    if text {
        chart
            .configure_mesh()
            .x_desc("time from the test's first sample (s)")
            .y_desc("|F| (N)")
            .draw()?;
    }
    chart.draw_series(DashedLineSeries::new(
        [(0.0, limit), (duration, limit)],
        8,
        5,
        RED.stroke_width(2),
    ))?;
    let colour = verdict_colour(
        test.verdict
            .as_ref()
            .or(test.object.and_then(|o| run.verdict_of(o))),
    );
    chart.draw_series(LineSeries::new(
        test.samples.iter().map(|&(t, f)| (t - t0, f)),
        colour.stroke_width(2),
    ))?;
    Ok(())
}

fn caption(run: &MapCollector) -> String {
    let grid = if run.grid.is_some() {
        "grid classes, "
    } else {
        ""
    };
    format!(
        "{}: {grid}obstacles (orange), true objects (grey), track (purple), paths (green), pushes (blue movable, black static), viewpoints (cyan)",
        run.scenario.name
    )
}

/// The snapshot palette, with unknown cells lighter so the rest stands out.
fn cell_colour(class: CellClass) -> RGBColor {
    let [r, g, b, _] = match class {
        CellClass::Unknown => [215, 215, 215, 255],
        other => other.colour(),
    };
    RGBColor(r, g, b)
}

fn verdict_colour(verdict: Option<&Verdict>) -> RGBColor {
    match verdict {
        Some(v) if v.is_movable() => RGBColor(40, 90, 230),
        Some(_) => BLACK,
        None => UNTESTED,
    }
}

fn closed(corners: &[Point2<f64>], style: ShapeStyle) -> PathElement<(f64, f64)> {
    let mut points: Vec<(f64, f64)> = corners.iter().map(|p| (p.x, p.y)).collect();
    if let Some(&first) = points.first() {
        points.push(first);
    }
    PathElement::new(points, style)
}

fn centroid(corners: &[Point2<f64>]) -> Option<Point2<f64>> {
    (!corners.is_empty()).then(|| {
        let sum = corners.iter().fold(Vector2::zeros(), |a, p| a + p.coords);
        Point2::from(sum / corners.len() as f64)
    })
}

/// The outline of a look-around's span from `at` facing `yaw`: two edges `half` either side and the
/// arc between them, [`VIEW_WEDGE`] long.
fn wedge(at: Point2<f64>, yaw: f64, half: f64) -> Vec<(f64, f64)> {
    const ARC: usize = 24;
    let point = |a: f64| (at.x + VIEW_WEDGE * a.cos(), at.y + VIEW_WEDGE * a.sin());
    let mut out = vec![(at.x, at.y)];
    out.extend((0..=ARC).map(|k| point(yaw - half + 2.0 * half * k as f64 / ARC as f64)));
    out.push((at.x, at.y));
    out
}

/// A shaft and a two-stroke head, 0.12 m long.
fn arrow(from: Point2<f64>, to: Point2<f64>, colour: RGBColor) -> Vec<PathElement<(f64, f64)>> {
    let d = (to - from).try_normalize(1e-9).unwrap_or_else(Vector2::x);
    let side = Vector2::new(-d.y, d.x);
    let head = |s: f64| {
        let p = to - d * 0.12 + side * (0.06 * s);
        vec![(p.x, p.y), (to.x, to.y)]
    };
    let style = colour.stroke_width(3);
    vec![
        PathElement::new(vec![(from.x, from.y), (to.x, to.y)], style),
        PathElement::new(head(1.0), style),
        PathElement::new(head(-1.0), style),
    ]
}
