//! A glTF file's node hierarchy: checked for cycles and depth, and the LOD
//! levels its nodes name (`MSFT_lod` ids, `_LOD<n>` suffixes), for
//! [`crate::gltf_mesh`], whose module docs give the rules.

use std::collections::HashMap;

/// Deepest node hierarchy accepted (and the guard against cycles).
pub(crate) const MAX_NODE_DEPTH: usize = 256;

/// Refuses a node hierarchy with a cycle (a node its own ancestor) or
/// deeper than [`MAX_NODE_DEPTH`], checked over every node.
pub(crate) fn check_hierarchy(doc: &gltf::Document) -> Result<(), String> {
    // 0: not seen, 1: on the current path, 2: done.
    let mut state = vec![0u8; doc.nodes().len()];
    for start in doc.nodes() {
        if state[start.index()] != 0 {
            continue;
        }
        let mut stack: Vec<(gltf::Node, gltf::scene::iter::Children)> =
            vec![(start.clone(), start.children())];
        state[start.index()] = 1;
        while let Some((node, children)) = stack.last_mut() {
            match children.next() {
                Some(c) => match state[c.index()] {
                    1 => {
                        return Err(format!(
                            "node {} is its own ancestor (the node hierarchy has a cycle)",
                            c.index()
                        ));
                    }
                    0 => {
                        if stack.len() >= MAX_NODE_DEPTH {
                            return Err(format!(
                                "node hierarchy deeper than {MAX_NODE_DEPTH} levels"
                            ));
                        }
                        state[c.index()] = 1;
                        let grand = c.children();
                        stack.push((c, grand));
                    }
                    _ => {}
                },
                None => {
                    state[node.index()] = 2;
                    stack.pop();
                }
            }
        }
    }
    Ok(())
}

/// The `_LOD<n>` suffix of a name (any case), if any.
pub(crate) fn lod_suffix(name: &str) -> Option<usize> {
    let at = name.to_ascii_lowercase().rfind("_lod")?;
    let digits = &name[at + 4..];
    if digits.is_empty() || digits.len() > 3 || !digits.bytes().all(|c| c.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// Node index -> its `MSFT_lod` ids (nodes of LOD 1, 2, ...), checked;
/// nodes without the extension or with no ids are absent.
pub(crate) fn msft_lod_ids(doc: &gltf::Document) -> Result<HashMap<usize, Vec<usize>>, String> {
    let n_nodes = doc.nodes().len();
    let mut out = HashMap::new();
    for node in doc.nodes() {
        let Some(ext) = node.extension_value("MSFT_lod") else {
            continue;
        };
        let at = format!("node {} extensions.MSFT_lod.ids", node.index());
        let ids = ext
            .get("ids")
            .and_then(|v| v.as_array())
            .ok_or_else(|| format!("{at}: missing or not an array"))?;
        let mut level_nodes = Vec::with_capacity(ids.len());
        for (k, id) in ids.iter().enumerate() {
            match id.as_u64() {
                Some(i) if (i as usize) < n_nodes => level_nodes.push(i as usize),
                _ => {
                    return Err(format!(
                        "{at}[{k}] = {id} is not a node index (0..{n_nodes})"
                    ));
                }
            }
        }
        if !level_nodes.is_empty() {
            out.insert(node.index(), level_nodes);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lod_suffixes() {
        assert_eq!(lod_suffix("rock_LOD0"), Some(0));
        assert_eq!(lod_suffix("rock_lod12"), Some(12));
        assert_eq!(lod_suffix("rock_LOD"), None);
        assert_eq!(lod_suffix("rock_LODx"), None);
        assert_eq!(lod_suffix("rock"), None);
    }
}
