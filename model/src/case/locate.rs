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

/// Dotted path of the deepest key whose value contains byte `offset` (for parser messages that
/// give a position but not the key). Tables opened by a `[header]` have spans that cover only
/// the header, so the search descends into every table rather than following spans.
pub fn key_at(text: &str, offset: usize) -> Option<String> {
    use toml::de::{DeTable, DeValue};
    fn walk(value: &DeValue<'_>, offset: usize, path: &mut Vec<String>) -> bool {
        let children: Vec<(String, &toml::Spanned<DeValue<'_>>, std::ops::Range<usize>)> = match value {
            DeValue::Table(t) => t.iter().map(|(k, v)| (k.get_ref().to_string(), v, k.span())).collect(),
            DeValue::Array(items) => items.iter().enumerate().map(|(i, v)| (i.to_string(), v, v.span())).collect(),
            _ => return false,
        };
        for (name, child, key_span) in children {
            path.push(name);
            if walk(child.get_ref(), offset, path) {
                return true;
            }
            let scalar = !matches!(child.get_ref(), DeValue::Table(_) | DeValue::Array(_));
            if key_span.contains(&offset) || (scalar && child.span().contains(&offset)) {
                return true;
            }
            path.pop();
        }
        false
    }
    let root = DeTable::parse(text).ok()?;
    let mut path = Vec::new();
    walk(&DeValue::Table(root.into_inner()), offset, &mut path).then(|| path.join("."))
}

/// Dotted key path of what line `line` (1-based) sets, read from the text alone (for files the
/// TOML parser refuses): the last `[table]` or `[[array]]` header above it (an array's entry
/// numbered from 0) and the `key =` on it, the header itself on a header line, the enclosing
/// table on a comment or blank line; `None` before any key or table.
pub fn key_of_line(text: &str, line: usize) -> Option<String> {
    let mut table: Option<String> = None;
    let mut arrays: std::collections::BTreeMap<String, usize> = std::collections::BTreeMap::new();
    let dotted = |s: &str| s.split('.').map(|p| p.trim().trim_matches('"')).collect::<Vec<_>>().join(".");
    for (i, raw) in text.lines().enumerate() {
        let trimmed = raw.trim();
        if let Some(header) = trimmed.strip_prefix('[') {
            let array = header.starts_with('[');
            let header = header.trim_start_matches('[');
            let name = dotted(&header[..header.find(']').unwrap_or(header.len())]);
            table = Some(if array {
                let n = arrays.entry(name.clone()).and_modify(|n| *n += 1).or_insert(0);
                format!("{name}.{n}")
            } else {
                name
            });
            if i + 1 == line {
                return table;
            }
            continue;
        }
        if i + 1 == line {
            if trimmed.is_empty() || trimmed.starts_with('#') {
                return table;
            }
            let key = trimmed.split('=').next().unwrap_or("").split_whitespace().next().map(dotted).filter(|k| !k.is_empty());
            return match (table, key) {
                (Some(t), Some(k)) => Some(format!("{t}.{k}")),
                (t, k) => k.or(t),
            };
        }
    }
    table
}
