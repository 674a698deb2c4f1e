//! The command line's allocator policy: keep freed memory in the process.
//!
//! glibc returns the top of its heap to the system when more than its trim threshold
//! is free (128 KiB by default, adjusted as large blocks come and go). A run of
//! `certmesh mesh` frees the mesher's buffers and then allocates the report's: every
//! page given back and asked for again costs a page fault (about 1.5 µs per 4 KiB
//! page measured on the development machine, `papers/bench-report.md`), and the
//! report, short as it is, paid several hundred of them. A process that lives for one
//! run gains nothing by giving memory back early, so the threshold is raised to
//! [`TRIM_THRESHOLD`], and blocks up to [`MMAP_THRESHOLD`] come from the heap. A
//! `GLIBC_TUNABLES` setting of the user's with `malloc` in it is left alone. The
//! figures are in `papers/bench-report.md`.

/// Free memory (bytes) at the top of the heap that glibc keeps rather than returns.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const TRIM_THRESHOLD: libc::c_int = 1 << 30;
/// Blocks from this size up are mapped (and unmapped when freed) on their own: 32 MiB,
/// the largest glibc accepts on 64-bit systems. Setting the trim threshold alone would
/// freeze this at its default of 128 KiB, and every buffer above that would be mapped
/// afresh: the 256³ marching-cubes torus took 16,200 page faults by default, 21,000–
/// 26,000 with the trim threshold alone, 13,900 with both.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const MMAP_THRESHOLD: libc::c_int = 32 << 20;

/// Set the policy (once, at the start of `main`, before any thread exists).
pub fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        let user = std::env::var("GLIBC_TUNABLES").is_ok_and(|t| t.contains("malloc"));
        if !user {
            // SAFETY: mallopt only sets a parameter of the allocator; it is called
            // before any other thread exists. Its result (0 when glibc refuses the
            // value) leaves the default policy, which is correct, only slower.
            unsafe {
                libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD);
                libc::mallopt(libc::M_TRIM_THRESHOLD, TRIM_THRESHOLD);
            }
        }
    }
}
