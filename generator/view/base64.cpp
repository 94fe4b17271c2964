#include "view/base64.hpp"

namespace mbgen::view {

std::string base64(const void* data, std::size_t size) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (std::size_t i = 0; i < size; i += 3) {
    const unsigned b0 = bytes[i], b1 = i + 1 < size ? bytes[i + 1] : 0u, b2 = i + 2 < size ? bytes[i + 2] : 0u;
    out += alphabet[b0 >> 2];
    out += alphabet[((b0 & 3u) << 4) | (b1 >> 4)];
    out += i + 1 < size ? alphabet[((b1 & 15u) << 2) | (b2 >> 6)] : '=';
    out += i + 2 < size ? alphabet[b2 & 63u] : '=';
  }
  return out;
}

}  // namespace mbgen::view
