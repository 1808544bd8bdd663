//! Comments on the canvas, markdown-ish: `# ` and `## ` headings, `**bold**`
//! spans, `- ` or `* ` list items, plain paragraphs. Painted in canvas
//! coordinates behind the nodes, so they zoom with the patch.

use egui::text::{LayoutJob, TextFormat};
use egui::{Color32, FontId, Painter, Pos2, Rect, Vec2};
use spreadlight_graph::CommentDoc;

use crate::canvas_units::SCALE;

/// Body text size of comments, as the nodes' (egui's body text).
const BODY: f32 = 12.5;

pub use super::measure::line_style;

/// The comment's rectangle in canvas points (snarl's coordinates).
pub fn rect(comment: &CommentDoc) -> Rect {
    let (w, h) = super::measure::comment_size(&comment.text);
    Rect::from_min_size(
        Pos2::new(comment.pos.0 * SCALE, comment.pos.1 * SCALE),
        Vec2::new(w * SCALE, h * SCALE),
    )
}

/// One line as a layout job: headings larger, `**bold**` spans in the strong colour.
fn line_job(line: &str, text: Color32, strong: Color32) -> LayoutJob {
    let (scale, body) = line_style(line);
    let heading = scale > 1.0;
    let bullet = body.len() != line.len() && !heading;
    let mut job = LayoutJob::default();
    let font = FontId::proportional(BODY * scale);
    let plain = TextFormat::simple(font.clone(), if heading { strong } else { text });
    let bold = TextFormat::simple(font, strong);
    if bullet {
        job.append("• ", 0.0, plain.clone());
    }
    for (k, part) in body.split("**").enumerate() {
        // Odd parts lie between a pair of `**`.
        let format = if k % 2 == 1 { &bold } else { &plain };
        job.append(part, 0.0, format.clone());
    }
    job
}

/// Paint the comments (in canvas points), with `offset` added to comment `moving`.
pub fn paint(painter: &Painter, comments: &[CommentDoc], moving: Option<(usize, Vec2)>) {
    let style = painter.ctx().global_style();
    let visuals = &style.visuals;
    let text = visuals.text_color();
    let strong = visuals.strong_text_color();
    for (i, c) in comments.iter().enumerate() {
        let mut r = rect(c);
        if let Some((m, d)) = moving
            && m == i
        {
            r = r.translate(d);
        }
        if !painter.clip_rect().intersects(r) {
            continue;
        }
        painter.rect_filled(r, 3.0, Color32::from_rgba_unmultiplied(40, 40, 30, 120));
        let mut y = r.min.y + 4.0;
        for line in c.text.lines() {
            let (scale, _) = line_style(line);
            let galley = painter.layout_job(line_job(line, text, strong));
            painter.galley(Pos2::new(r.min.x + 8.0, y), galley, text);
            y += super::measure::LINE_H * scale;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markup_sets_the_size_and_is_not_shown() {
        assert_eq!(line_style("# Title"), (1.5, "Title"));
        assert_eq!(line_style("## Part"), (1.25, "Part"));
        assert_eq!(line_style("- item"), (1.0, "item"));
        assert_eq!(line_style("plain"), (1.0, "plain"));
        let job = line_job("- a **b** c", Color32::GRAY, Color32::WHITE);
        assert_eq!(job.text, "• a b c");
        let colors: Vec<Color32> = job.sections.iter().map(|s| s.format.color).collect();
        // Neighbouring spans of one format are merged.
        assert_eq!(colors, vec![Color32::GRAY, Color32::WHITE, Color32::GRAY]);
    }
}
