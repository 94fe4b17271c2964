#pragma once
// Base64 (RFC 4648, with padding): how a page of `mbgen view` carries binary data, its meshes'
// arrays and its scripts as data URLs.
#include <cstddef>
#include <string>

namespace mbgen::view {

std::string base64(const void* data, std::size_t size);

inline std::string base64(const std::string& text) { return base64(text.data(), text.size()); }

}  // namespace mbgen::view
