//! `index.html`: the report as one page readable offline, with no script
//! (plots are inline SVG, folded in `<details>`), red where a section is
//! incomplete.

use std::fmt::Write as _;

use super::closed_loop::Figure;
use super::requirements::Citation;
use super::{Report, Status};

/// Escapes `text` for HTML.
#[must_use]
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

const STYLE: &str = "body{font-family:sans-serif;margin:1.5em;max-width:1400px}\
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #bbb;padding:2px 6px;\
vertical-align:top;font-size:90%}th{background:#eee}.fail{background:#fdd;color:#900}\
.pass{color:#060}.skipped{background:#ffd;color:#850}.banner{padding:.6em;font-size:120%;\
font-weight:bold}code{font-size:90%}svg{max-width:100%;height:auto}";

/// The status as a `<span>` of its class.
fn badge(status: Status) -> String {
    format!(
        "<span class=\"{}\">{}</span>",
        class(status),
        status.label()
    )
}

const fn class(status: Status) -> &'static str {
    match status {
        Status::Pass => "pass",
        Status::Fail => "fail",
        Status::Skipped => "skipped",
    }
}

/// A list of problems in red.
fn problems(list: &[String]) -> String {
    if list.is_empty() {
        return String::new();
    }
    let items: String = list
        .iter()
        .map(|p| format!("<li>{}</li>", escape(p)))
        .collect();
    format!("<ul class=\"fail\">{items}</ul>")
}

fn figure_value(v: Option<f64>) -> String {
    v.map_or_else(|| "—".to_owned(), |v| format!("{v:.4}"))
}

/// The figures of a run or a sweep, one per line, red when beyond the bound.
fn figures(list: &[Figure]) -> String {
    list.iter()
        .map(|f| {
            let bound = f
                .bound
                .map_or_else(String::new, |b| format!(" (bound ≤ {b})"));
            let cls = match f.pass {
                Some(false) => " class=\"fail\"",
                _ => "",
            };
            format!(
                "<div{cls}>{}: {}{}</div>",
                escape(&f.name),
                figure_value(f.value),
                escape(&bound)
            )
        })
        .collect()
}

fn citations(list: &[Citation]) -> String {
    list.iter()
        .map(|c| {
            format!(
                "<div><code>{}</code> {}</div>",
                escape(&c.at),
                escape(&c.item)
            )
        })
        .collect()
}

/// An SVG to embed: without its XML prolog; never one holding a script.
fn inline_svg(text: &str) -> String {
    if text.to_ascii_lowercase().contains("<script") {
        return "<p class=\"fail\">plot not embedded: it holds a script</p>".to_owned();
    }
    let body = text
        .find("<svg")
        .and_then(|i| text.get(i..))
        .unwrap_or(text);
    body.to_owned()
}

/// The whole page.
#[must_use]
pub fn render(r: &Report) -> String {
    let mut h = String::new();
    let p = &r.provenance;
    let commit = p.commit.as_deref().unwrap_or("unknown");
    let _ = write!(
        h,
        "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>fieldguide evidence {}</title><style>{STYLE}</style></head><body>\
         <h1>fieldguide: evidence for a safety assessor</h1>",
        escape(commit)
    );
    let verdict = match r.status {
        Status::Pass => "complete: every section passed",
        Status::Fail => "INCOMPLETE: a section failed (in red below); this is not evidence",
        Status::Skipped => "incomplete: a section was deliberately skipped",
    };
    let _ = write!(
        h,
        "<p class=\"banner {}\">Report {}</p>\
         <p>Commit <code>{}</code>{}, made {}.</p>\
         <table><tr><th>section</th><th>status</th></tr>\
         <tr><td><a href=\"#provenance\">Provenance</a></td><td>{}</td></tr>\
         <tr><td><a href=\"#requirements\">Requirements</a></td><td>{}</td></tr>\
         <tr><td><a href=\"#proofs\">Proofs</a></td><td>{}</td></tr>\
         <tr><td><a href=\"#closed-loop\">Closed loop</a></td><td>{}</td></tr>\
         <tr><td><a href=\"#benchmarks\">Benchmarks</a></td><td>{}</td></tr></table>",
        class(r.status),
        verdict,
        escape(commit),
        if p.dirty == Some(true) {
            " <span class=\"fail\">with uncommitted changes</span>"
        } else {
            ""
        },
        escape(&p.date),
        badge(p.status),
        badge(r.requirements.status),
        badge(r.proofs.status),
        badge(r.closed_loop.status),
        badge(r.benchmarks.status),
    );

    // Requirements.
    let m = &r.requirements;
    let _ = write!(
        h,
        "<h2 id=\"requirements\">Requirements {}</h2>{}\
         <p>Every requirement of <code>spec/</code>, with the items that implement it and the \
         tests, proofs and closed-loop scenarios that check it, from duvet's JSON report.</p>\
         <table><tr><th>spec file</th><th>requirements</th><th>implemented</th><th>tested</th>\
         <th>complete</th></tr>",
        badge(m.status),
        problems(&m.problems)
    );
    for f in &m.files {
        let cls = if f.complete == f.requirements {
            ""
        } else {
            " class=\"fail\""
        };
        let _ = write!(
            h,
            "<tr{cls}><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&f.file),
            f.requirements,
            f.implemented,
            f.tested,
            f.complete
        );
    }
    let total: usize = m.files.iter().map(|f| f.requirements).sum();
    let complete: usize = m.files.iter().map(|f| f.complete).sum();
    let _ = write!(
        h,
        "<tr><th>all</th><th>{total}</th><th></th><th></th><th>{complete}</th></tr></table>\
         <table><tr><th>ID</th><th>requirement</th><th>source and reading</th>\
         <th>implemented by</th><th>tests</th><th>proofs</th><th>scenarios</th></tr>"
    );
    for q in &m.requirements {
        let cls = if q.status == Status::Fail {
            " class=\"fail\""
        } else {
            ""
        };
        let mut source = String::new();
        if let Some(s) = &q.source {
            let _ = write!(source, "<div><b>Source:</b> {}</div>", escape(s));
        }
        if let Some(s) = &q.reading {
            let _ = write!(source, "<div><b>Reading:</b> {}</div>", escape(s));
        }
        let _ = write!(
            h,
            "<tr{cls}><td><b>{}</b></td><td>{}<br><small>{}</small></td><td>{source}</td>\
             <td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&q.id),
            escape(&q.title),
            escape(&q.file),
            citations(&q.implementations),
            citations(&q.tests),
            citations(&q.proofs),
            citations(&q.scenarios)
        );
    }
    h.push_str("</table>");

    // Proofs.
    let _ = write!(
        h,
        "<h2 id=\"proofs\">Proofs {}</h2>{}\
         <p>Each stateright model, bolero harness and mutant of <code>proofs/tests</code>, as it \
         recorded itself when <code>cargo test -p fieldguide-proofs</code> ran at this commit.</p>\
         <table><tr><th>proof</th><th>kind</th><th>status</th><th>explored</th>\
         <th>duration</th><th>properties checked</th></tr>",
        badge(r.proofs.status),
        problems(&r.proofs.problems)
    );
    for proof in &r.proofs.proofs {
        let cls = if proof.status == Status::Fail {
            " class=\"fail\""
        } else {
            ""
        };
        let (kind, explored, duration, properties) = proof.record.as_ref().map_or_else(
            || (String::new(), String::new(), String::new(), String::new()),
            |rec| {
                let mut e = Vec::new();
                let mut add = |label: &str, v: Option<u64>| {
                    if let Some(v) = v {
                        e.push(format!("{v} {label}"));
                    }
                };
                add("states", rec.states);
                add("transitions", rec.transitions);
                add("sequences", rec.sequences);
                add("ticks deep", rec.depth);
                if let Some(fault) = &rec.mutant {
                    e.push(format!("mutant {fault} caught"));
                }
                (
                    escape(&rec.kind),
                    escape(&e.join(", ")),
                    format!("{:.2} s", rec.duration_s),
                    escape(&rec.properties.join("; ")),
                )
            },
        );
        let _ = write!(
            h,
            "<tr{cls}><td>{}<br><small>{}</small></td><td>{kind}</td><td>{}</td><td>{explored}</td>\
             <td>{duration}</td><td><small>{properties}</small></td></tr>",
            escape(&proof.name),
            escape(&proof.file),
            proof
                .problem
                .as_ref()
                .map_or_else(|| badge(proof.status), |why| escape(why)),
        );
    }
    h.push_str("</table>");

    // Closed loop.
    let c = &r.closed_loop;
    let _ = write!(
        h,
        "<h2 id=\"closed-loop\">Closed loop {}</h2>{}\
         <p>Every built-in scenario, run for this report as <code>cargo run --release</code> runs \
         it; errors against ground truth. Plots fold out.</p>\
         <table><tr><th>scenario</th><th>kind</th><th>verdict</th><th>figures</th>\
         <th>plots</th></tr>",
        badge(c.status),
        problems(&c.problems)
    );
    for run in &c.runs {
        let (row, verdict) = match (run.pass, run.expected) {
            (true, _) => ("", badge(Status::Pass)),
            (false, Some(why)) => (
                "skipped",
                format!(
                    "<span class=\"skipped\">breaks its bounds on purpose</span>: {}",
                    escape(why)
                ),
            ),
            (false, None) => ("fail", badge(Status::Fail)),
        };
        let plots: String = run
            .plots
            .iter()
            .map(|plot| match &plot.svg {
                Some(svg) => format!("<h4>{}</h4>{}", escape(&plot.file), inline_svg(svg)),
                None => format!(
                    "<p>{}: in <code>{}/</code> beside this folder</p>",
                    escape(&plot.file),
                    escape(&run.name)
                ),
            })
            .collect();
        let _ = write!(
            h,
            "<tr class=\"{row}\"><td>{}</td><td>{}</td><td>{verdict}{}</td><td>{}</td>\
             <td><details><summary>{} plots</summary>{plots}</details></td></tr>",
            escape(&run.name),
            run.family,
            problems(&run.failures),
            figures(&run.figures),
            run.plots.len()
        );
    }
    h.push_str(
        "</table><h3>Sweeps</h3><p>The worst figure over the seeds against the scenario's \
         bound; seeds whose run broke a bound are listed.</p><table><tr><th>sweep</th>\
         <th>seeds</th><th>verdict</th><th>worst figures</th><th>seeds that broke a bound</th></tr>",
    );
    for s in &c.sweeps {
        let failed: String = s
            .failed_seeds
            .iter()
            .map(|(seed, why)| format!("<div>seed {seed}: {}</div>", escape(&why.join("; "))))
            .collect();
        let _ = write!(
            h,
            "<tr class=\"{}\"><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{failed}</td></tr>",
            if s.pass { "" } else { "fail" },
            escape(&s.name),
            escape(&s.seeds),
            badge(if s.pass { Status::Pass } else { Status::Fail }),
            figures(&s.figures)
        );
    }
    h.push_str("</table>");

    // Benchmarks.
    let b = &r.benchmarks;
    let _ = write!(
        h,
        "<h2 id=\"benchmarks\">Benchmarks {}</h2>{}",
        badge(b.status),
        problems(&b.problems)
    );
    if b.status == Status::Skipped {
        h.push_str("<p class=\"skipped\">Deliberately skipped (--no-benchmarks).</p>");
    }
    if let Some(machine) = &b.machine {
        let _ = write!(
            h,
            "<p>Criterion's last run{}, median time per iteration with its 95 % interval. \
             Machine: {} ({} logical cores).</p>",
            b.measured
                .as_ref()
                .map_or_else(String::new, |d| format!(", written {}", escape(d))),
            escape(&machine.cpu),
            machine.cores
        );
    }
    if !b.benchmarks.is_empty() {
        h.push_str("<table><tr><th>benchmark</th><th>median</th><th>95 % interval</th></tr>");
        for x in &b.benchmarks {
            let _ = write!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{} – {}</td></tr>",
                escape(&x.id),
                time(x.median_ns),
                time(x.interval_ns.0),
                time(x.interval_ns.1)
            );
        }
        h.push_str("</table>");
    }

    // Provenance.
    let _ = write!(
        h,
        "<h2 id=\"provenance\">Provenance {}</h2>{}<table>\
         <tr><th>commit</th><td><code>{}</code></td></tr>\
         <tr><th>uncommitted changes</th><td>{}</td></tr>\
         <tr><th>rustc</th><td>{}</td></tr><tr><th>cargo</th><td>{}</td></tr>\
         <tr><th>date</th><td>{}</td></tr></table>\
         <details><summary>{} packages (the workspace and every dependency) with their \
         licences</summary><table><tr><th>package</th><th>version</th><th>licence</th></tr>",
        badge(p.status),
        problems(&p.problems),
        escape(commit),
        p.dirty.map_or("unknown", |d| if d { "yes" } else { "no" }),
        escape(p.rustc.as_deref().unwrap_or("unknown")),
        escape(p.cargo.as_deref().unwrap_or("unknown")),
        escape(&p.date),
        p.dependencies.len()
    );
    for d in &p.dependencies {
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&d.name),
            escape(&d.version),
            escape(d.license.as_deref().unwrap_or("none declared"))
        );
    }
    h.push_str("</table></details></body></html>\n");
    h
}

/// Nanoseconds in a readable unit.
fn time(ns: f64) -> String {
    if ns >= 1e6 {
        format!("{:.3} ms", ns / 1e6)
    } else if ns >= 1e3 {
        format!("{:.3} µs", ns / 1e3)
    } else {
        format!("{ns:.1} ns")
    }
}
