//! `gpu::keep_freed_memory`: memory freed and allocated again is not faulted in again.
//! (lavapipe frees and mallocs its per-draw buffers every frame; with glibc's default
//! thresholds the fig9g viewer took about 3 000 page faults a frame.) Its own test
//! binary: the process's fault counter must not see other tests' allocations.

#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[test]
fn a_block_freed_and_allocated_again_is_not_faulted_in_again() {
    use sediment::gpu::{keep_freed_memory, minor_page_faults};

    // Below glibc's largest mmap threshold, above its default one (128 KiB): by
    // default the first such block is mapped and unmapped, the second comes from a
    // heap that grows for it, and both fault in every page.
    const BYTES: usize = 16 << 20;
    let faults = || minor_page_faults().expect("Linux counts page faults");
    let round = || {
        let before = faults();
        // Ones, not zeros: a zeroed block could come from untouched pages.
        let block = std::hint::black_box(vec![1u8; BYTES]);
        drop(block);
        faults() - before
    };
    keep_freed_memory();
    let first = round();
    let second = round();
    let pages = (BYTES / 4096) as u64;
    assert!(
        first >= pages / 2,
        "the first 16 MiB block faulted {first} pages in, expected about {pages}"
    );
    assert!(
        second < pages / 16,
        "the same block allocated again faulted {second} pages in (the first {first}): \
         the freed memory went back to the kernel"
    );
}
