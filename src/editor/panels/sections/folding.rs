//! Which of the panel's sections are open: each folds open or shut with a click on its title,
//! and the open ones are remembered between runs in `$XDG_STATE_HOME/pappus/panel-sections`
//! (one title a line, beside the recoveries); a file that cannot be read or written only costs
//! that memory.

use std::collections::BTreeSet;
use std::path::PathBuf;

use bevy::prelude::Resource;
use bevy_egui::egui;

use super::SECTIONS;

/// Which sections are open, and where that is remembered.
#[derive(Resource, Debug)]
pub struct PanelSections {
    open: BTreeSet<String>,
    file: Option<PathBuf>,
}

impl Default for PanelSections {
    /// The sections as last left ([`SECTIONS`]' defaults the first time).
    fn default() -> Self {
        let file = crate::recovery::folder()
            .and_then(|recoveries| Some(recoveries.parent()?.join("panel-sections")));
        Self::read(file)
    }
}

impl PanelSections {
    /// The open sections as listed in `file`, or the defaults without one.
    pub fn read(file: Option<PathBuf>) -> Self {
        let open = match file.as_ref().and_then(|f| std::fs::read_to_string(f).ok()) {
            Some(text) => text
                .lines()
                .map(str::trim)
                .filter(|title| SECTIONS.iter().any(|s| s.title == *title))
                .map(str::to_owned)
                .collect(),
            None => SECTIONS
                .iter()
                .filter(|s| s.open_at_first)
                .map(|s| s.title.to_owned())
                .collect(),
        };
        Self { open, file }
    }

    /// Whether the section titled `title` is open.
    pub fn is_open(&self, title: &str) -> bool {
        self.open.contains(title)
    }

    /// Opens or shuts a section, and remembers it.
    pub fn set_open(&mut self, title: &str, open: bool) {
        let changed = match open {
            true => self.open.insert(title.to_owned()),
            false => self.open.remove(title),
        };
        if changed {
            self.write();
        }
    }

    /// Draws the section titled `title` with `contents` when it is open; a click on the title
    /// folds it.
    pub fn show(&mut self, ui: &mut egui::Ui, title: &str, contents: impl FnOnce(&mut egui::Ui)) {
        crate::checks::checked_assert!(
            SECTIONS.iter().any(|s| s.title == title),
            "{title} is not in SECTIONS"
        );
        let open = self.is_open(title);
        let shown = egui::CollapsingHeader::new(egui::RichText::new(title).strong())
            .id_salt(title)
            .open(Some(open))
            .show(ui, contents);
        if shown.header_response.clicked() {
            self.set_open(title, !open);
        }
    }

    fn write(&self) {
        let Some(file) = &self.file else {
            return;
        };
        let text: String = self.open.iter().map(|t| format!("{t}\n")).collect();
        if let Some(folder) = file.parent()
            && let Err(e) = std::fs::create_dir_all(folder)
        {
            bevy::log::warn!(
                "the panel's sections are not remembered: {}: {e}",
                folder.display()
            );
            return;
        }
        // Written as a mesh is saved: a crash mid-write leaves the last list whole.
        if let Err(e) = crate::io::replace_file(file, text.as_bytes()) {
            bevy::log::warn!("the panel's sections are not remembered: {e}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_sections_are_remembered_in_their_file_and_unknown_lines_ignored() {
        let file = std::env::temp_dir().join(format!("pappus-sections-{}", std::process::id()));
        std::fs::remove_file(&file).ok();
        let mut sections = PanelSections::read(Some(file.clone()));
        assert!(sections.is_open("File") && !sections.is_open("Whole mesh"));
        sections.set_open("Whole mesh", true);
        sections.set_open("File", false);
        let again = PanelSections::read(Some(file.clone()));
        assert!(again.is_open("Whole mesh") && !again.is_open("File"));
        std::fs::write(&file, "Log\nno such section\n").unwrap();
        let odd = PanelSections::read(Some(file.clone()));
        assert_eq!(odd.open.iter().collect::<Vec<_>>(), ["Log"]);
        std::fs::remove_file(&file).ok();
        // Without a file: the defaults, and nothing written.
        let none = PanelSections::read(None);
        assert!(none.is_open("Element") && !none.is_open("History"));
    }
}
