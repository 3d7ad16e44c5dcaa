#include "io/hash.h"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <vector>

#include "plumb/error.h"

namespace plumb::internal {

namespace {

// FNV-1a, 64 bits: plumb's hash of files and compiled models (a fingerprint, not security).
class Fnv1a {
 public:
  void Add(const unsigned char* bytes, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      h_ ^= bytes[i];
      h_ *= 0x100000001b3ULL;
    }
  }
  std::string Hex() const {
    char hex[17];
    std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(h_));
    return hex;
  }

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

}  // namespace

std::string HashFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot read '" + path + "' to hash it");
  Fnv1a hash;
  char buffer[65536];
  while (in.read(buffer, sizeof(buffer)) || in.gcount() > 0) {
    hash.Add(reinterpret_cast<const unsigned char*>(buffer), static_cast<std::size_t>(in.gcount()));
  }
  return hash.Hex();
}

std::string HashModel(const Model& model) {
  const mjModel* m = model.get();
  std::vector<unsigned char> buffer(static_cast<std::size_t>(mj_sizeModel(m)));
  mj_saveModel(m, nullptr, buffer.data(), static_cast<int>(buffer.size()));
  Fnv1a hash;
  hash.Add(buffer.data(), buffer.size());
  return hash.Hex();
}

}  // namespace plumb::internal
