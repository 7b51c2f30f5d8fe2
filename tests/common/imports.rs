//! Which source files of a crate import each other.
//!
//! A file *imports* another when one of its `use` trees or inline paths (`crate::…`,
//! `super::…`, `self::…`, or a child module's name in `use`) names an item that lives in the
//! other file. An item reached through a re-export (`pub use a::b::Item` in `lib.rs` or a
//! `mod.rs`) counts as an import of the file that defines it, not of the re-exporting file.
//! `#[cfg(test)] mod tests` at the end of a file is not counted, and `mod x;` declarations are
//! not imports.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A module path inside one crate (`[]` is the root).
type ModPath = Vec<String>;

struct Crate {
    files: BTreeMap<ModPath, PathBuf>,
    /// Per module: re-exported item name → the full path it points to.
    reexports: BTreeMap<ModPath, BTreeMap<String, ModPath>>,
    /// Per module: every use path and inline path, as written (not yet resolved).
    paths: BTreeMap<ModPath, Vec<ModPath>>,
}

fn module_path(src: &Path, file: &Path) -> ModPath {
    let rel = file.strip_prefix(src).expect("under src");
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts
}

/// The code of a file without comments, string literals or its trailing test module.
fn code_of(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let mut end = lines.len();
    for (i, l) in lines.iter().enumerate() {
        if l.trim() == "#[cfg(test)]"
            && lines
                .get(i + 1)
                .is_some_and(|n| n.trim_start().starts_with("mod "))
        {
            end = i;
            break;
        }
    }
    let mut out = String::new();
    for l in &lines[..end] {
        let code = match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        };
        out.push_str(code);
        out.push('\n');
    }
    // Blank out string literals so paths inside messages are not read as code.
    let mut clean = String::with_capacity(out.len());
    let mut in_str = false;
    let mut prev = ' ';
    for c in out.chars() {
        if c == '"' && prev != '\\' && prev != '\'' {
            in_str = !in_str;
            clean.push(' ');
        } else if in_str {
            clean.push(if c == '\n' { '\n' } else { ' ' });
        } else {
            clean.push(c);
        }
        prev = c;
    }
    clean
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Expands a use tree (`a::{b::C, d}`) into its paths.
fn expand_use_tree(tree: &str) -> Vec<ModPath> {
    // Drop renames (`X as Y`) first, then white space.
    let mut kept = Vec::new();
    let mut tokens = tree.split_whitespace().peekable();
    while let Some(t) = tokens.next() {
        if t == "as" {
            let renamed = tokens.next().unwrap_or("");
            kept.push(renamed.trim_start_matches(is_ident).to_string());
        } else {
            kept.push(t.to_string());
        }
    }
    let tree: String = kept.concat();
    fn split_top(s: &str) -> Vec<&str> {
        let (mut depth, mut start, mut out) = (0, 0, Vec::new());
        for (i, c) in s.char_indices() {
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    out.push(&s[start..i]);
                    start = i + 1;
                }
                _ => {}
            }
        }
        out.push(&s[start..]);
        out.into_iter().filter(|p| !p.is_empty()).collect()
    }
    fn go(prefix: &[String], s: &str, out: &mut Vec<ModPath>) {
        if let Some(open) = s.find('{') {
            let head = s[..open].trim_end_matches("::");
            let inner = s[open + 1..].trim_end_matches('}');
            let mut p = prefix.to_vec();
            p.extend(head.split("::").filter(|x| !x.is_empty()).map(String::from));
            for part in split_top(inner) {
                go(&p, part, out);
            }
        } else {
            let mut p = prefix.to_vec();
            p.extend(s.split("::").filter(|x| !x.is_empty()).map(String::from));
            out.push(p);
        }
    }
    let mut out = Vec::new();
    go(&[], &tree, &mut out);
    out
}

/// `use` trees (with whether they are `pub use`) and inline `crate::`/`super::` paths.
fn scan(code: &str) -> (Vec<(bool, ModPath)>, Vec<ModPath>) {
    let mut uses = Vec::new();
    let mut inline = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find("use ") {
        let before = &rest[..i];
        let boundary = before.chars().last().is_none_or(|c| !is_ident(c));
        let after = &rest[i + 4..];
        if boundary {
            if let Some(end) = after.find(';') {
                let tree = &after[..end];
                let public = before.trim_end().ends_with("pub") || before.trim_end().ends_with(')');
                // Skip `use` inside identifiers such as `reuse ` (boundary handled above).
                for p in expand_use_tree(tree) {
                    uses.push((public, p));
                }
            }
        }
        rest = after;
    }
    for key in ["crate::", "super::", "self::"] {
        let mut from = 0;
        while let Some(i) = code[from..].find(key) {
            let at = from + i;
            from = at + key.len();
            if code[..at].chars().last().is_some_and(is_ident) {
                continue;
            }
            let tail = &code[at..];
            let end = tail
                .find(|c: char| !(is_ident(c) || c == ':'))
                .unwrap_or(tail.len());
            let path: ModPath = tail[..end]
                .split("::")
                .filter(|x| !x.is_empty())
                .map(String::from)
                .collect();
            inline.push(path);
        }
    }
    (uses, inline)
}

fn absolute(current: &ModPath, path: &ModPath, children: &BTreeSet<String>) -> Option<ModPath> {
    let mut base = current.clone();
    let mut segs = path.as_slice();
    match segs.first().map(String::as_str) {
        Some("crate") => {
            base.clear();
            segs = &segs[1..];
        }
        Some("self") => segs = &segs[1..],
        Some("super") => {
            while segs.first().map(String::as_str) == Some("super") {
                base.pop()?;
                segs = &segs[1..];
            }
        }
        Some(first) if children.contains(first) => {}
        _ => return None,
    }
    base.extend(segs.iter().cloned());
    Some(base)
}

impl Crate {
    fn read(src: &Path) -> Crate {
        let mut files = BTreeMap::new();
        fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
            for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
                let p = e.path();
                if p.is_dir() {
                    walk(&p, out);
                } else if p.extension().is_some_and(|x| x == "rs") {
                    out.push(p);
                }
            }
        }
        let mut all = Vec::new();
        walk(src, &mut all);
        for f in all {
            // Binaries under src/bin are crates of their own.
            if f.strip_prefix(src).is_ok_and(|r| r.starts_with("bin")) {
                continue;
            }
            files.insert(module_path(src, &f), f);
        }
        let mut reexports = BTreeMap::new();
        let mut paths = BTreeMap::new();
        for (m, f) in &files {
            let code = code_of(&std::fs::read_to_string(f).expect("readable"));
            let (uses, inline) = scan(&code);
            let children = children_of(&files, m);
            let mut re = BTreeMap::new();
            let mut ps = Vec::new();
            for (public, p) in uses {
                if let Some(abs) = absolute(m, &p, &children) {
                    if public {
                        if let Some(last) = abs.last() {
                            re.insert(last.clone(), abs.clone());
                        }
                    }
                    ps.push(abs);
                }
            }
            for p in inline {
                if let Some(abs) = absolute(m, &p, &children) {
                    ps.push(abs);
                }
            }
            reexports.insert(m.clone(), re);
            paths.insert(m.clone(), ps);
        }
        Crate {
            files,
            reexports,
            paths,
        }
    }

    /// The module (file) that defines what `path` names.
    fn resolve(&self, path: &ModPath, depth: usize) -> Option<ModPath> {
        let mut k = path.len();
        while k > 0 && !self.files.contains_key(&path[..k]) {
            k -= 1;
        }
        let module: ModPath = path[..k].to_vec();
        if !self.files.contains_key(&module) {
            return None;
        }
        if let (Some(item), true) = (path.get(k), depth < 8) {
            if let Some(target) = self.reexports.get(&module).and_then(|r| r.get(item)) {
                if target != path {
                    return self.resolve(target, depth + 1).or(Some(module));
                }
            }
        }
        Some(module)
    }
}

fn children_of(files: &BTreeMap<ModPath, PathBuf>, m: &ModPath) -> BTreeSet<String> {
    files
        .keys()
        .filter(|k| k.len() == m.len() + 1 && k.starts_with(m))
        .filter_map(|k| k.last().cloned())
        .collect()
}

/// Pairs of files of the crate whose sources are under `src` that import each other.
pub fn import_pairs(src: &Path) -> Vec<(PathBuf, PathBuf)> {
    if !src.is_dir() {
        return Vec::new();
    }
    let krate = Crate::read(src);
    let mut edges: BTreeSet<(ModPath, ModPath)> = BTreeSet::new();
    for (m, ps) in &krate.paths {
        for p in ps {
            if let Some(target) = krate.resolve(p, 0) {
                if &target != m {
                    edges.insert((m.clone(), target));
                }
            }
        }
    }
    let mut out = Vec::new();
    for (a, b) in &edges {
        if a < b && edges.contains(&(b.clone(), a.clone())) {
            out.push((krate.files[a].clone(), krate.files[b].clone()));
        }
    }
    out
}
