// The C library's heap set for a process that works frame after frame (the CLI, the node, the
// benchmarks); not part of the core's algorithms, which never call it.
#pragma once

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace virtual_tryon {

// glibc gives the top of its heap back to the system whenever more than 128 KiB lie free there,
// and serves blocks past its (moving) mapping threshold from fresh mappings, unmapped on free. A
// process that builds and drops the same large arrays frame after frame then takes the same pages
// back again and again; on a virtual machine those page faults cost more than the work (the walk's
// first resolved frame: about 52 -> 31 ms). Kept instead: 64 MiB free at the top of the heap, and
// blocks up to 32 MiB served from the heap. A no-op on other C libraries.
inline void keepHeapForFrames() {
#if defined(__GLIBC__)
  mallopt(M_TOP_PAD, 64 << 20);
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
#endif
}

}  // namespace virtual_tryon
