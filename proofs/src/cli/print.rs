//! Human-readable and JSON output of runs and checks.
use super::fail::Fail;
use proofs::gradnormal::Certificate;
use proofs::stuffing;

/// The label of a shard's output.
pub(crate) fn shard_line(shard: [usize; 2], of: &str) -> String {
    format!(
        "shard {}/{}: a partial result, not a proof of {of} (`proofs merge` the {} shards for one)",
        shard[0], shard[1], shard[1]
    )
}

pub(crate) fn print_human(c: &Certificate) {
    println!(
        "GradNormal angle proof: a/e = {}, rule = {}, {} of {} cases, {:.2} s",
        c.ratio,
        c.rule,
        c.cases.len(),
        c.n_cases,
        c.seconds
    );
    if let Some(s) = c.shard {
        println!("  {}", shard_line(s, "the claims"));
    }
    if let Some(s) = &c.summary {
        println!(
            "  smallest projected angle in [{:.9}°, {:.9}°]",
            s.min_deg[0], s.min_deg[1]
        );
        println!(
            "  largest projected angle  in [{:.9}°, {:.9}°]",
            s.max_deg[0], s.max_deg[1]
        );
        println!(
            "  valence-four triangles: [{:.7}°, {:.7}°] .. [{:.7}°, {:.7}°]",
            s.v4_min_deg[0], s.v4_min_deg[1], s.v4_max_deg[0], s.v4_max_deg[1]
        );
        for cl in &c.claims {
            println!("  {:9} {}", cl.verdict.name(), cl.claim);
        }
    }
}

pub(crate) fn gradnormal_json(cert: &Certificate, out: &std::path::Path) -> serde_json::Value {
    serde_json::json!({
        "ratio": cert.ratio,
        "rule": cert.rule,
        "seconds": cert.seconds,
        "certificate": out.display().to_string(),
        "partial": cert.partial,
        "shard": cert.shard.map(|s| format!("{}/{}", s[0], s[1])),
        "min_deg": cert.summary.as_ref().map(|s| s.min_deg),
        "max_deg": cert.summary.as_ref().map(|s| s.max_deg),
        "v4_min_deg": cert.summary.as_ref().map(|s| s.v4_min_deg),
        "v4_max_deg": cert.summary.as_ref().map(|s| s.v4_max_deg),
        "claims": cert.claims,
        "cases": cert.summary.as_ref().map(|s| &s.cases),
    })
}

pub(crate) fn print_json(v: &serde_json::Value) -> Result<(), Fail> {
    println!(
        "{}",
        serde_json::to_string_pretty(v).map_err(|e| Fail::input(e.to_string()))?
    );
    Ok(())
}

pub(crate) fn print_bound(b: &stuffing::BoundResult, partial: bool) {
    let paper = b
        .paper
        .map(|x| format!("{x:.4}"))
        .unwrap_or_else(|| "n/a".into());
    let deg = b
        .deg
        .map(|d| format!("[{:.6}, {:.6}]", d[0], d[1]))
        .unwrap_or_else(|| "n/a".into());
    println!(
        "  {:13} paper {:>9}  {} {:24}  {:9}  tight: {}",
        b.bound,
        paper,
        if partial { "this shard" } else { "certified " },
        deg,
        b.verdict.map(|v| v.name()).unwrap_or("-"),
        b.tight.as_deref().unwrap_or("-")
    );
}

pub(crate) fn print_stuffing(c: &stuffing::Certificate) {
    println!(
        "stuffing row {}: {} -> {} cases, {} problems, {} leaves ({} unresolved), {:.1} s",
        c.row,
        c.counts.raw,
        c.counts.distinct,
        c.problems.len(),
        c.leaves,
        c.unresolved,
        c.seconds
    );
    if let Some(s) = c.shard {
        println!("  {}", shard_line(s, "the row"));
    }
    for b in &c.bounds {
        print_bound(b, c.partial);
    }
    println!(
        "  safe{}: {} (min volume / unwarped volume = {:.6}; {} -> {} cases){}",
        if c.partial {
            " (decided on every BCC case, not sharded)"
        } else {
            ""
        },
        c.safe.verdict.name(),
        c.safe.min_ratio,
        c.safe.counts.raw,
        c.safe.counts.distinct,
        if c.safe.note.is_empty() {
            String::new()
        } else {
            format!("; {}", c.safe.note)
        }
    );
    if let Some(a) = stuffing::custom::audit(c) {
        if let Some(r) = a.table1_row {
            println!("  these are the parameters of Table 1 row {r} (run `--row {r}` for verdicts against its paper values)");
        }
        println!("  audit: {}", a.verdict);
    }
}

/// The first line of `proofs check`, for either kind of certificate.
pub(crate) fn print_check_ok(what: &str, leaves: usize, complete: bool, t0: std::time::Instant) {
    println!(
        "certificate OK: {what}, {leaves} leaves re-evaluated{} ({:.2} s)",
        if complete {
            ", complete"
        } else {
            " (partial: a shard)"
        },
        t0.elapsed().as_secs_f64()
    );
}
