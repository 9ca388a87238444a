//! The requirement matrix: every `### ID: title` section of `spec/*.md`, its
//! source and reading, and the items and checks that cite it, taken from
//! duvet's own JSON report (`duvet report --json`).
//!
//! A requirement without an implementation or without a test citation is
//! red; so is a duvet that cannot run or whose `--ci` check fails.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;
use serde_json::Value;

use super::{command, Status};

/// One requirement of `spec/`.
#[derive(Debug, Clone, Serialize)]
pub struct Requirement {
    /// Its stable ID (`PT-MODEL`).
    pub id: String,
    /// Its title.
    pub title: String,
    /// The spec file (`spec/pierre2022.md`): the paper.
    pub file: String,
    /// The `- Source:` paragraph (paper section, equation), if any.
    pub source: Option<String>,
    /// The `- Reading:` paragraph (the chosen reading or erratum), if any.
    pub reading: Option<String>,
    /// The implementing items (`file:line` and the item's first line).
    pub implementations: Vec<Citation>,
    /// Test citations in `tests/` and `sim/src` test files.
    pub tests: Vec<Citation>,
    /// Test citations in `proofs/`.
    pub proofs: Vec<Citation>,
    /// Test citations in `sim/tests/` (closed-loop scenarios).
    pub scenarios: Vec<Citation>,
    /// Complete: at least one implementation and one test of any kind.
    pub status: Status,
}

/// Where a requirement is cited.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Citation {
    /// `file:line` of the citation.
    pub at: String,
    /// The first line of the item under it (`pub fn law(`).
    pub item: String,
}

/// Counts of one spec file.
#[derive(Debug, Clone, Serialize)]
pub struct FileCount {
    /// The spec file.
    pub file: String,
    /// Its requirements.
    pub requirements: usize,
    /// With an implementation citation.
    pub implemented: usize,
    /// With a test, proof or scenario citation.
    pub tested: usize,
    /// With both.
    pub complete: usize,
}

/// The matrix.
#[derive(Debug, Clone, Serialize)]
pub struct Matrix {
    /// `fail` when a requirement lacks a citation or duvet failed.
    pub status: Status,
    /// What is wrong, in words.
    pub problems: Vec<String>,
    /// Per spec file.
    pub files: Vec<FileCount>,
    /// Every requirement, in file order.
    pub requirements: Vec<Requirement>,
}

/// Reads `root/spec/*.md`, runs `duvet` in `root` and joins the two.
#[must_use]
pub fn gather(root: &Path, duvet: &Path) -> Matrix {
    let mut problems = Vec::new();
    let mut requirements = match parse_specs(&root.join("spec")) {
        Ok(r) => r,
        Err(e) => {
            problems.push(e);
            Vec::new()
        }
    };
    if requirements.is_empty() {
        problems.push("no `### ID: title` requirement found in spec/*.md".to_owned());
    }
    let (citations, duvet_failed) = match run_duvet(root, duvet) {
        Ok(found) => found,
        Err(e) => (BTreeMap::new(), Some(e)),
    };
    problems.extend(duvet_failed);
    for r in &mut requirements {
        for (kind, (file, line)) in citations
            .get(&(r.file.clone(), r.heading()))
            .map_or(&[][..], Vec::as_slice)
        {
            let (line, item) = item_at(root, file, *line);
            let citation = Citation {
                at: format!("{file}:{line}"),
                item,
            };
            let list = match kind {
                Kind::Implementation => &mut r.implementations,
                Kind::Test if file.starts_with("proofs/") => &mut r.proofs,
                Kind::Test if file.starts_with("sim/tests/") => &mut r.scenarios,
                Kind::Test => &mut r.tests,
            };
            // An item citing several sentences of the requirement: once.
            if !list.contains(&citation) {
                list.push(citation);
            }
        }
        let tested = !(r.tests.is_empty() && r.proofs.is_empty() && r.scenarios.is_empty());
        if r.implementations.is_empty() || !tested {
            r.status = Status::Fail;
            problems.push(format!(
                "{} ({}) has no {}",
                r.id,
                r.file,
                if r.implementations.is_empty() {
                    "implementation citation"
                } else {
                    "test citation"
                }
            ));
        }
    }
    let mut files: Vec<FileCount> = Vec::new();
    for r in &requirements {
        if files.last().is_none_or(|f| f.file != r.file) {
            files.push(FileCount {
                file: r.file.clone(),
                requirements: 0,
                implemented: 0,
                tested: 0,
                complete: 0,
            });
        }
        if let Some(f) = files.last_mut() {
            let implemented = !r.implementations.is_empty();
            let tested = !(r.tests.is_empty() && r.proofs.is_empty() && r.scenarios.is_empty());
            f.requirements += 1;
            f.implemented += usize::from(implemented);
            f.tested += usize::from(tested);
            f.complete += usize::from(implemented && tested);
        }
    }
    Matrix {
        status: Status::of(&problems),
        problems,
        files,
        requirements,
    }
}

impl Requirement {
    fn new(file: &str, id: &str, title: &str) -> Self {
        Self {
            id: id.trim().to_owned(),
            title: title.trim().to_owned(),
            file: file.to_owned(),
            source: None,
            reading: None,
            implementations: Vec::new(),
            tests: Vec::new(),
            proofs: Vec::new(),
            scenarios: Vec::new(),
            status: Status::Pass,
        }
    }

    /// The heading as written after `### ` (`PT-MODEL: extended …`).
    fn heading(&self) -> String {
        format!("{}: {}", self.id, self.title)
    }
}

/// Every requirement of the `*.md` files of `dir`, files in name order.
///
/// # Errors
/// When the folder or a file cannot be read.
pub fn parse_specs(dir: &Path) -> Result<Vec<Requirement>, String> {
    let read_dir = |e: std::io::Error| format!("{}: {e}", dir.display());
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .map_err(read_dir)?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    files.sort();
    let mut all = Vec::new();
    for path in files {
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let name = path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        all.extend(parse_spec(&format!("spec/{name}"), &text));
    }
    Ok(all)
}

/// The requirements of one spec file's `text`.
#[must_use]
pub fn parse_spec(file: &str, text: &str) -> Vec<Requirement> {
    let mut out = Vec::new();
    let mut current: Option<(Requirement, Vec<&str>)> = None;
    let mut fenced = false;
    let finish = |out: &mut Vec<Requirement>, current: Option<(Requirement, Vec<&str>)>| {
        if let Some((mut r, body)) = current {
            r.source = paragraph(&body, "- Source:");
            r.reading = paragraph(&body, "- Reading:");
            out.push(r);
        }
    };
    for line in text.lines() {
        if line.starts_with("```") {
            fenced = !fenced;
        }
        if line.starts_with('#') && !fenced {
            // Any heading ends the requirement's body.
            finish(&mut out, current.take());
            current = line
                .strip_prefix("### ")
                .and_then(|h| h.split_once(": "))
                .map(|(id, title)| (Requirement::new(file, id, title), Vec::new()));
        } else if let Some((_, body)) = current.as_mut() {
            body.push(line);
        }
    }
    finish(&mut out, current);
    out
}

/// The bullet starting with `marker` and its indented continuation lines,
/// joined on one line.
fn paragraph(body: &[&str], marker: &str) -> Option<String> {
    let start = body.iter().position(|l| l.starts_with(marker))?;
    let mut text = body
        .get(start)?
        .trim_start_matches(marker)
        .trim()
        .to_owned();
    for line in body.iter().skip(start + 1) {
        if line.starts_with("  ") && !line.trim().is_empty() {
            text.push(' ');
            text.push_str(line.trim());
        } else {
            break;
        }
    }
    Some(text)
}

/// What a citation is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Implementation,
    Test,
}

/// The citations duvet found: (spec file, heading) → (kind, (file, line)).
type Citations = BTreeMap<(String, String), Vec<(Kind, (String, u64))>>;

/// Runs `duvet report --ci --require-citations true --require-tests true
/// --json` in `root` and reads its JSON: the citations, and duvet's own
/// check failing, in words (its JSON is still read then).
///
/// # Errors
/// When duvet cannot run or writes no readable JSON.
fn run_duvet(root: &Path, duvet: &Path) -> Result<(Citations, Option<String>), String> {
    let dir = std::env::temp_dir().join(format!(
        "fieldguide-evidence-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let json = dir.join("duvet.json");
    let json_arg = json.to_string_lossy().into_owned();
    let ran = command(
        duvet,
        &[
            "report",
            "--ci",
            "--require-citations",
            "true",
            "--require-tests",
            "true",
            "--json",
            &json_arg,
        ],
        root,
    );
    let text = std::fs::read_to_string(&json);
    let _ = std::fs::remove_dir_all(&dir);
    let check = ran.err().map(|e| format!("duvet: {e}"));
    let text = text.map_err(|e| {
        check
            .clone()
            .unwrap_or_else(|| format!("duvet wrote no JSON report: {e}"))
    })?;
    let report: Value =
        serde_json::from_str(&text).map_err(|e| format!("duvet's JSON report: {e}"))?;
    Ok((citations(&report)?, check))
}

/// The citations of duvet's JSON report (`--json`): the annotations without
/// a type or of type `CITATION`/`IMPLEMENTATION` implement, `TEST` tests.
fn citations(report: &Value) -> Result<Citations, String> {
    let mut headings: BTreeMap<(String, String), String> = BTreeMap::new();
    let specs = report
        .get("specifications")
        .and_then(Value::as_object)
        .ok_or("duvet's JSON report has no `specifications`")?;
    for (file, spec) in specs {
        let sections = spec.get("sections").and_then(Value::as_array);
        for section in sections.into_iter().flatten() {
            if let (Some(id), Some(title)) = (
                section.get("id").and_then(Value::as_str),
                section.get("title").and_then(Value::as_str),
            ) {
                headings.insert((file.clone(), id.to_owned()), title.to_owned());
            }
        }
    }
    let annotations = report
        .get("annotations")
        .and_then(Value::as_array)
        .ok_or("duvet's JSON report has no `annotations`")?;
    let mut out = Citations::new();
    for a in annotations {
        let text = |k: &str| a.get(k).and_then(Value::as_str).unwrap_or("");
        let kind = match text("type") {
            "" | "CITATION" | "IMPLEMENTATION" => Kind::Implementation,
            "TEST" => Kind::Test,
            _ => continue,
        };
        let key = (
            text("target_path").to_owned(),
            text("target_section").to_owned(),
        );
        let Some(heading) = headings.get(&key) else {
            continue;
        };
        let line = a.get("line").and_then(Value::as_u64).unwrap_or(0);
        let at = (text("source").to_owned(), line);
        out.entry((key.0, heading.clone()))
            .or_default()
            .push((kind, at));
    }
    Ok(out)
}

/// The line and the text of the first line of code at or under `line` of
/// `file` (the item a citation stands above).
fn item_at(root: &Path, file: &str, line: u64) -> (u64, String) {
    let Ok(text) = std::fs::read_to_string(root.join(file)) else {
        return (line, String::new());
    };
    let skip = usize::try_from(line.saturating_sub(1)).unwrap_or(0);
    text.lines()
        .enumerate()
        .skip(skip)
        .map(|(i, l)| (i, l.trim()))
        .find(|(_, l)| !(l.is_empty() || l.starts_with("//") || l.starts_with("#[")))
        .map_or((line, String::new()), |(i, l)| {
            (
                u64::try_from(i).map_or(line, |i| i + 1),
                l.chars().take(100).collect(),
            )
        })
}
