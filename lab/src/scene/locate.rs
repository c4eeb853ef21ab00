//! Places in the scene text: byte offsets as 1-based lines and columns,
//! and field paths (`objects[2].copies.count`) to and from spans of the
//! parsed TOML document, so errors name the field and point at its line.

use std::ops::Range;

use toml::de::{DeTable, DeValue};

/// 1-based line and column (in characters) of a byte offset; offsets past
/// the end or inside a character are clamped.
pub(super) fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}

enum Seg<'a> {
    Key(&'a str),
    Index(usize),
}

fn segments(field: &str) -> Vec<Seg<'_>> {
    let mut out = Vec::new();
    for part in field.split('.') {
        let mut pieces = part.split('[');
        if let Some(key) = pieces.next()
            && !key.is_empty()
        {
            out.push(Seg::Key(key));
        }
        for idx in pieces {
            if let Ok(i) = idx.trim_end_matches(']').parse() {
                out.push(Seg::Index(i));
            }
        }
    }
    out
}

/// The span of the deepest part of `field` present in the document: the key
/// for a table entry, the element for an array index.
pub(super) fn locate(root: &DeTable<'_>, field: &str) -> Option<Range<usize>> {
    let mut best = None;
    let mut current: Option<&DeValue<'_>> = None;
    for seg in segments(field) {
        match seg {
            Seg::Key(k) => {
                let table = match current {
                    None => root,
                    Some(v) => match v.as_table() {
                        Some(t) => t,
                        None => break,
                    },
                };
                let Some((key, value)) = table.iter().find(|(key, _)| key.get_ref() == k) else {
                    break;
                };
                best = Some(key.span());
                current = Some(value.get_ref());
            }
            Seg::Index(i) => {
                let Some(item) = current.and_then(|v| v.as_array()).and_then(|a| a.get(i)) else {
                    break;
                };
                best = Some(item.span());
                current = Some(item.get_ref());
            }
        }
    }
    best
}

fn contains(span: &Range<usize>, offset: usize) -> bool {
    span.contains(&offset) || (span.start == offset && span.end == offset)
}

/// The field path of the deepest key or element whose span holds `offset`
/// ("" when none does). The whole tree is searched: a `[table]` header's span
/// covers only the header, not the keys under it.
pub(super) fn field_at(root: &DeTable<'_>, offset: usize) -> String {
    find_in_table(root, offset, "").unwrap_or_default()
}

fn find_in_table(table: &DeTable<'_>, offset: usize, prefix: &str) -> Option<String> {
    for (k, v) in table.iter() {
        let path = if prefix.is_empty() {
            k.get_ref().to_string()
        } else {
            format!("{prefix}.{}", k.get_ref())
        };
        let deeper = find_in_value(v.get_ref(), offset, &path);
        if deeper.is_some() {
            return deeper;
        }
        if contains(&k.span(), offset) || contains(&v.span(), offset) {
            return Some(path);
        }
    }
    None
}

fn find_in_value(value: &DeValue<'_>, offset: usize, path: &str) -> Option<String> {
    match value {
        DeValue::Table(t) => find_in_table(t, offset, path),
        DeValue::Array(a) => a.iter().enumerate().find_map(|(i, item)| {
            let item_path = format!("{path}[{i}]");
            find_in_value(item.get_ref(), offset, &item_path)
                .or_else(|| contains(&item.span(), offset).then_some(item_path))
        }),
        _ => None,
    }
}
