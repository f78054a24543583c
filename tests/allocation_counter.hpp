#pragma once
// Counts every allocation of the test program that includes this (once, in its one translation
// unit): the no-allocation-per-frame tests compare g_allocations before and after a frame.
#include <atomic>
#include <cstdlib>
#include <new>

static std::atomic<long> g_allocations{0};
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// The nothrow form too (std::stable_sort's buffer): else a sanitizer's own would allocate what
// the delete above frees (AddressSanitizer: alloc-dealloc-mismatch).
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  ++g_allocations;
  return std::malloc(n ? n : 1);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
