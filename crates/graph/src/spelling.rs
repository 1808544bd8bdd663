//! The known name nearest a misspelled one: what "did you mean" messages
//! suggest for an unknown node type (`CookTorance` -> `CookTorrance`).
//!
//! Distance is the optimal-string-alignment edit distance (insert, delete,
//! substitute, or swap two neighbours: the usual typing slips), on
//! lowercase characters, so `cooktorrance` finds `CookTorrance` at 0.

/// Edits that turn `a` into `b`: insertions, deletions, substitutions and
/// swaps of two neighbouring characters, each counting 1; case is ignored.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().flat_map(char::to_lowercase).collect();
    let b: Vec<char> = b.chars().flat_map(char::to_lowercase).collect();
    // Three rows of the dynamic programme: two back (for swaps), one back, this one.
    let mut two_back: Vec<usize> = vec![0; b.len() + 1];
    let mut one_back: Vec<usize> = (0..=b.len()).collect();
    let mut row: Vec<usize> = vec![0; b.len() + 1];
    for i in 1..=a.len() {
        row[0] = i;
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut best = (one_back[j] + 1)
                .min(row[j - 1] + 1)
                .min(one_back[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(two_back[j - 2] + 1);
            }
            row[j] = best;
        }
        std::mem::swap(&mut two_back, &mut one_back);
        std::mem::swap(&mut one_back, &mut row);
    }
    one_back[b.len()]
}

/// The candidate nearest `name`, when it is near enough to be a slip of
/// the keyboard rather than another word: at most a third of the name's
/// length in edits (at least 1), the length counted without a category in
/// brackets, which names share (`Teleporter (Spreads)` is no slip of
/// `Reverse (Spreads)`). Ties go to the first candidate.
pub fn nearest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let base = name.split_once(" (").map_or(name, |(base, _)| base);
    let allowed = (base.chars().count() / 3).max(1);
    let mut best: Option<(usize, &str)> = None;
    for candidate in candidates {
        let d = edit_distance(name, candidate);
        if d <= allowed && best.is_none_or(|(b, _)| d < b) {
            best = Some((d, candidate));
        }
    }
    best.map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_count_each_kind_of_slip_once() {
        assert_eq!(edit_distance("CookTorrance", "CookTorrance"), 0);
        assert_eq!(edit_distance("cooktorrance", "CookTorrance"), 0);
        // A letter left out, one too many, one wrong, two swapped.
        assert_eq!(edit_distance("CookTorance", "CookTorrance"), 1);
        assert_eq!(edit_distance("CookTorrrance", "CookTorrance"), 1);
        assert_eq!(edit_distance("CookTerrance", "CookTorrance"), 1);
        assert_eq!(edit_distance("CookTorrnace", "CookTorrance"), 1);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("abc", ""), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }

    #[test]
    fn the_nearest_name_is_suggested_only_when_near() {
        let names = [
            "CompositeLight",
            "CookTorrance",
            "Noise (Shader)",
            "Output",
            "Reverse (Spreads)",
            "Tonemap",
        ];
        assert_eq!(nearest("CookTorance", names), Some("CookTorrance"));
        assert_eq!(nearest("Ouptut", names), Some("Output"));
        assert_eq!(nearest("tonemap", names), Some("Tonemap"));
        assert_eq!(nearest("Nosie (Shader)", names), Some("Noise (Shader)"));
        // Another word altogether is no slip.
        assert_eq!(nearest("Teleporter (Spreads)", names), None);
        assert_eq!(nearest("X", names), None);
    }
}
