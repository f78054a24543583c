#pragma once
// printf-style appending to a string (private to sim/).
#include <cstdarg>
#include <cstdio>
#include <string>

namespace acuity::sim {

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
inline void
appendf(std::string* out, const char* format, ...) {
  va_list args, copy;
  va_start(args, format);
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, format, copy);
  va_end(copy);
  if (n > 0) {
    const std::size_t at = out->size();
    out->resize(at + std::size_t(n) + 1);
    std::vsnprintf(out->data() + at, std::size_t(n) + 1, format, args);
    out->resize(at + std::size_t(n));
  }
  va_end(args);
}

}  // namespace acuity::sim
