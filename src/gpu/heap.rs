//! Keeping a software driver's freed memory in the process.
//!
//! lavapipe's draw module (vertex and geometry stages, on the submitting thread)
//! allocates its vertex outputs with `malloc` for every draw and frees them after. By
//! default glibc hands the top of the heap back to the kernel once more than 128 KiB
//! of it is free (and serves large blocks with their own `mmap`), so the next draw
//! page-faults the same megabytes in again and the kernel zeroes them, every frame.
//! Raising both thresholds keeps that memory in the process for the next draw. Peak
//! memory is unchanged; what was freed is only not returned.

/// Raises glibc's trim and mmap thresholds, once per process; does nothing with any
/// other C library. `Context::new` calls it for a CPU device.
pub fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        static ONCE: std::sync::Once = std::sync::Once::new();
        ONCE.call_once(|| {
            // glibc's largest mmap threshold on 64-bit (its DEFAULT_MMAP_THRESHOLD_MAX):
            // blocks below it come from the heap.
            const MMAP_THRESHOLD: libc::c_int = 32 << 20;
            const TRIM_THRESHOLD: libc::c_int = 1 << 30;
            // SAFETY: mallopt only sets allocator parameters; glibc takes its arena
            // lock, so other threads may be allocating meanwhile.
            let ok = unsafe {
                libc::mallopt(libc::M_TRIM_THRESHOLD, TRIM_THRESHOLD) == 1
                    && libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD) == 1
            };
            if !ok {
                log::debug!(
                    "mallopt refused the heap thresholds; the driver's memory is trimmed as usual"
                );
            }
        });
    }
}

/// Minor page faults of the whole process so far (every thread: the driver's
/// rasteriser threads too), where the platform counts them; the bench reports them
/// per frame (`bench::PAGE_FAULTS`).
pub fn minor_page_faults() -> Option<u64> {
    #[cfg(target_os = "linux")]
    {
        let mut usage = std::mem::MaybeUninit::<libc::rusage>::zeroed();
        // SAFETY: getrusage writes one rusage into the pointer it is given.
        let ok = unsafe { libc::getrusage(libc::RUSAGE_SELF, usage.as_mut_ptr()) } == 0;
        // SAFETY: zeroed is a valid rusage, and getrusage filled it on success.
        let usage = unsafe { usage.assume_init() };
        ok.then(|| u64::try_from(usage.ru_minflt).unwrap_or(0))
    }
    #[cfg(not(target_os = "linux"))]
    {
        None
    }
}
