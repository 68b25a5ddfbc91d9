#pragma once
// Transparent huge pages for the whole process's malloc, where the kernel gives them only to
// memory that asks for them (THP mode "madvise", Debian's default).
//
// glibc's malloc asks (madvise(MADV_HUGEPAGE) on its heaps) only under the tunable
// glibc.malloc.hugetlb=1, which it reads before main runs. So when GLIBC_TUNABLES is unset and
// the mode is "madvise", this sets it and executes the same program again with the same
// arguments (same process id, open files and environment otherwise); it returns when nothing is
// to be done or the exec failed, and the program runs on with 4 KiB pages. A GLIBC_TUNABLES the
// user set is left as it is (GLIBC_TUNABLES= turns this off). Either way malloc's heaps then grow
// 64 MiB at a time (M_TOP_PAD), which huge pages need in the heaps of threads other than the main
// one (see the .cpp). Sanitizer builds, whose malloc is not glibc's, skip it.
//
// Why: a million-face cage allocates gigabytes in millions of blocks; faulting them in 4 KiB at
// a time was a quarter of planning and half of the first frame (docs/renderer.md,
// "Production-size cages").
namespace qp::cli {
void useHugePagesForMalloc(char** argv);
}
