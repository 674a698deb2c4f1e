//! The demo's HTML page in a real headless browser (Debian's chromium): the page loads
//! without JavaScript, shows the comparison table and every picture it names.
//! Run with `cargo test --test demo_page -- --ignored` after `apt-get install -y chromium`;
//! CERTMESH_KEEP_SCREENSHOT=1 keeps `shot.png` in the temporary folder to look at.
use certmesh::mesher::NoProgress;
use std::process::Command;

#[test]
#[ignore = "needs Debian's chromium (apt-get install -y chromium) and a quick demo run"]
fn the_demo_page_renders_in_a_headless_browser() {
    let d = std::env::temp_dir().join(format!("certmesh-demo-page-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let rep = certmesh::harness::demo::run(&d, true, &NoProgress).unwrap();
    let html = std::fs::read_to_string(d.join("index.html")).unwrap();
    assert!(!html.to_lowercase().contains("<script"), "no JavaScript");
    assert!(html.contains("<table>") && html.contains("<th>certificate</th>"));
    // Every picture named exists, and every surface run has one.
    let srcs: Vec<&str> = html
        .split("<img src=\"")
        .skip(1)
        .filter_map(|s| s.split('"').next())
        .collect();
    for s in &srcs {
        assert!(d.join(s).exists(), "missing picture {s}");
    }
    let drawn = rep
        .rows
        .iter()
        .filter(|r| r.error.is_none() && r.faces > 0)
        .count();
    assert!(
        srcs.len() >= drawn,
        "{} pictures for {drawn} runs",
        srcs.len()
    );
    let profile = d.join("profile");
    let shot = d.join("shot.png");
    let st = Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--no-first-run",
            "--hide-scrollbars",
            "--window-size=1400,1800",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("file://{}", d.join("index.html").display()))
        .status()
        .expect("chromium runs (apt-get install -y chromium)");
    assert!(st.success());
    let png = std::fs::read(&shot).unwrap();
    let mut r = png::Decoder::new(png.as_slice()).read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size()];
    let info = r.next_frame(&mut buf).unwrap();
    assert_eq!(info.width, 1400);
    let ch = info.color_type.samples();
    let px: Vec<&[u8]> = buf[..info.buffer_size()].chunks(ch).collect();
    let ink = px
        .iter()
        .filter(|p| p[0] < 200 || p[1] < 200 || p[2] < 200)
        .count();
    assert!(
        ink * 50 > px.len(),
        "the page is (nearly) blank: {ink} of {} pixels",
        px.len()
    );
    // The renderings loaded: the certificate colours appear (green or vermillion).
    let coloured = px
        .iter()
        .map(|p| [p[0] as i32, p[1] as i32, p[2] as i32])
        .filter(|p| (p[1] > p[0] + 40 && p[1] > p[2]) || (p[0] > 180 && p[1] < 120 && p[2] < 60))
        .count();
    assert!(
        coloured > 1000,
        "no rendering visible: {coloured} coloured pixels"
    );
    if std::env::var_os("CERTMESH_KEEP_SCREENSHOT").is_none() {
        let _ = std::fs::remove_dir_all(&d);
    } else {
        eprintln!("screenshot: {}", shot.display());
    }
}
