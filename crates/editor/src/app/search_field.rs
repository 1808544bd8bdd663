//! The search field the node browser and Find share: a text field whose
//! hits are walked with the arrow keys, Enter taking the highlighted one.

use egui::{Id, Key, Ui};

/// What a search field's keys asked for this frame.
pub(super) struct SearchKeys {
    pub enter: bool,
    pub escape: bool,
}

/// The field for `query` (focused when `focus` is set, which it clears),
/// with `highlighted` reset on typing and moved by the arrow keys within
/// `hits` results.
pub(super) fn search_field(
    ui: &mut Ui,
    (query, focus, highlighted): (&mut String, &mut bool, &mut usize),
    hits: usize,
    hint: &str,
    id: &str,
) -> SearchKeys {
    let (down, up, enter, escape) = ui.input(|i| {
        (
            i.key_pressed(Key::ArrowDown),
            i.key_pressed(Key::ArrowUp),
            i.key_pressed(Key::Enter),
            // egui takes Esc to unfocus the text field; the raw input still has it.
            i.raw.events.iter().any(|e| {
                matches!(
                    e,
                    egui::Event::Key {
                        key: Key::Escape,
                        pressed: true,
                        ..
                    }
                )
            }),
        )
    });
    let edit = ui.add(
        egui::TextEdit::singleline(query)
            .hint_text(hint)
            .id(Id::new(id)),
    );
    if *focus {
        edit.request_focus();
        *focus = false;
    }
    if edit.changed() {
        *highlighted = 0;
    }
    if down {
        *highlighted = (*highlighted + 1).min(hits.saturating_sub(1));
    }
    if up {
        *highlighted = highlighted.saturating_sub(1);
    }
    SearchKeys { enter, escape }
}
