#include "rasm/surfel_map/PodArray.h"

#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace rasm::maps::detail {

#if defined(__linux__)

namespace {
std::size_t pageBytes() {
  static const std::size_t page = std::size_t(sysconf(_SC_PAGESIZE));
  return page;
}
}  // namespace

std::size_t podRoundBytes(std::size_t bytes) {
  const std::size_t page = pageBytes();
  return (bytes + page - 1) / page * page;
}

void* podAllocate(std::size_t bytes) {
  void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  return p;
}

void* podGrow(void* p, std::size_t old_bytes, std::size_t new_bytes) {
  void* q = mremap(p, old_bytes, new_bytes, MREMAP_MAYMOVE);
  if (q == MAP_FAILED) throw std::bad_alloc();
  return q;
}

void podFree(void* p, std::size_t bytes) {
  if (p) munmap(p, bytes);
}

#else

std::size_t podRoundBytes(std::size_t bytes) {
  return (bytes + 63) / 64 * 64;
}

void* podAllocate(std::size_t bytes) {
  void* p = std::malloc(bytes);
  if (!p) throw std::bad_alloc();
  return p;
}

void* podGrow(void* p, std::size_t, std::size_t new_bytes) {
  void* q = std::realloc(p, new_bytes);
  if (!q) throw std::bad_alloc();
  return q;
}

void podFree(void* p, std::size_t) {
  std::free(p);
}

#endif

}  // namespace rasm::maps::detail
