//! The thread's own CPU time, for the benches that measure by it (`foot_cpu`, `map`):
//! on a shared VM the wall clock also measures the other tenants.
//! Included by `#[path = "common/cpu_time.rs"] mod cpu_time;`.

use std::time::Instant;

/// Seconds of CPU time this thread has used (wall time where there is no such clock).
#[cfg(unix)]
#[allow(unsafe_code)] // one libc call; the engines have none
pub fn cpu_s(_start: Instant) -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

#[cfg(not(unix))]
pub fn cpu_s(start: Instant) -> f64 {
    start.elapsed().as_secs_f64()
}
