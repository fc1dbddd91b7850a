//! Maps a dotted key path back to its line and column in the case text.

/// 1-based line and column of a byte offset.
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rfind('\n').map_or(before.chars().count(), |nl| before[nl + 1..].chars().count()) + 1;
    (line, column)
}

/// Position of the deepest existing key along `key_path` (`a.b.c`; a numeric segment indexes an
/// array of tables), pointing at the value when the full path exists.
pub fn key_position(text: &str, key_path: &str) -> Option<(usize, usize)> {
    use toml::de::{DeTable, DeValue};
    let root = DeTable::parse(text).ok()?;
    let mut table = root.get_ref();
    let mut best: Option<usize> = None;
    let mut segments = key_path.split('.').peekable();
    while let Some(seg) = segments.next() {
        let Some((key, value)) = table.iter().find(|(k, _)| k.get_ref().as_ref() == seg) else { break };
        best = Some(if segments.peek().is_none() { value.span().start } else { key.span().start });
        let mut value = value.get_ref();
        if let (DeValue::Array(items), Some(idx)) = (value, segments.peek().and_then(|s| s.parse::<usize>().ok())) {
            segments.next();
            let Some(item) = items.get(idx) else { break };
            best = Some(item.span().start);
            value = item.get_ref();
        }
        match value {
            DeValue::Table(t) => table = t,
            _ => break,
        }
    }
    best.map(|offset| line_column(text, offset))
}
