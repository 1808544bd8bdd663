//! The node browser's search: type a few letters of a name or category.

use spreadlight_graph::Registry;

/// Node type names matching `query`, best first. Every word of the query must
/// occur (case-insensitively) in the name or the category; names that start
/// with the query come first, as in vvvv. An empty query lists everything.
pub fn filter<'a>(registry: &'a Registry, query: &str) -> Vec<&'a str> {
    let words: Vec<String> = query.split_whitespace().map(str::to_lowercase).collect();
    let lower_query = query.trim().to_lowercase();
    let mut hits: Vec<(u8, &str, &str)> = registry
        .iter()
        .filter_map(|def| {
            let name = def.name.to_lowercase();
            let haystack = format!("{name} {}", def.category.to_lowercase());
            if !words.iter().all(|w| haystack.contains(w.as_str())) {
                return None;
            }
            let rank = if name == lower_query {
                0
            } else if name.starts_with(&lower_query) {
                1
            } else if name.contains(&lower_query) {
                2
            } else {
                3
            };
            Some((rank, &*def.category, &*def.name))
        })
        .collect();
    hits.sort();
    hits.into_iter().map(|(_, _, name)| name).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_type_is_listed_and_reachable_by_its_name() {
        let reg = spreadlight_nodes::registry();
        assert_eq!(filter(&reg, "").len(), reg.len());
        for def in reg.iter() {
            assert_eq!(
                filter(&reg, &def.name).first(),
                Some(&&*def.name),
                "typing the full name puts `{}` first",
                def.name
            );
        }
    }

    #[test]
    fn category_words_narrow_the_list() {
        let reg = spreadlight_nodes::registry();
        let lights = filter(&reg, "lighting");
        assert!(lights.contains(&"PointLightBuffer"), "{lights:?}");
        assert!(lights.iter().all(|n| {
            let d = reg.get(n).expect("def");
            d.category.to_lowercase().contains("lighting") || n.to_lowercase().contains("lighting")
        }));
        assert!(filter(&reg, "zzzz nothing").is_empty());
    }
}
