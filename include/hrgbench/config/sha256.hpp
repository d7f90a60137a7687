#pragma once
// SHA-256 (FIPS 180-4), small and self-contained: sessions record the hash of every config file
// that produced them (hrg-sim "spec_sha256", hrg-bench the station, sequence and limits hashes) so
// a session can be traced back to the exact bytes of its configs. Not constant-time and not meant
// for secrets; it only fingerprints files.

#include <array>
#include <cstddef>
#include <cstdint>
#include <expected>
#include <filesystem>
#include <string>
#include <string_view>

namespace hrgbench::config_file {

class Sha256 {
 public:
  Sha256() noexcept;

  // Feeds more bytes; may be called any number of times before Finish().
  void Update(std::string_view bytes) noexcept;
  // Pads, returns the 32-byte digest and resets the object for a new message.
  std::array<std::uint8_t, 32> Finish() noexcept;

 private:
  void Reset() noexcept;
  void Compress(const std::uint8_t* block) noexcept;

  std::array<std::uint32_t, 8> h_{};
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffer_used_ = 0;
  std::uint64_t total_bytes_ = 0;
};

// Lower-case hex of a digest.
std::string ToHex(const std::array<std::uint8_t, 32>& digest);

// Hex SHA-256 of a byte string.
std::string Sha256Hex(std::string_view bytes);

// Hex SHA-256 of a file's bytes; the error says which file could not be read and why.
std::expected<std::string, std::string> Sha256FileHex(const std::filesystem::path& path);

}  // namespace hrgbench::config_file
