#include "json_lines.hpp"

#include <algorithm>
#include <string>

namespace hrgbench::session::internal {
namespace {

// A minimal JSON walker over text that nlohmann has already accepted. Strings cannot contain raw
// newlines in valid JSON, so lines only need counting in whitespace. Keys are compared in their
// raw (escaped) form; session keys have no escapes.
class Locator {
 public:
  // Finds the value at path `target`, or with scalar_token: the scalar spelled `target`.
  Locator(std::string_view text, std::string_view target, bool scalar_token)
      : text_(text), target_(target), scalar_token_(scalar_token) {}

  std::size_t Find() {
    Value("", 0);
    return found_line_;
  }

  const std::string& found_path() const { return found_path_; }

 private:
  static constexpr int kMaxDepth = 256;

  // Returns false to stop the walk (target found or text not understood).
  bool Value(const std::string& path, int depth) {
    SkipSpace();
    if (!scalar_token_ && path == target_) {
      found_line_ = line_;
      return false;
    }
    if (pos_ >= text_.size() || depth > kMaxDepth) return false;
    const char c = text_[pos_];
    if (c == '{') return Object(path, depth);
    if (c == '[') return Array(path, depth);
    if (c == '"') return String(nullptr);
    const std::size_t start = pos_;
    while (pos_ < text_.size() &&
           std::string_view(",]} \t\r\n").find(text_[pos_]) == std::string_view::npos) {
      ++pos_;
    }
    if (scalar_token_ && text_.substr(start, pos_ - start) == target_) {
      found_line_ = line_;
      found_path_ = path;
      return false;
    }
    return true;
  }

  bool Object(const std::string& path, int depth) {
    ++pos_;
    SkipSpace();
    if (Peek() == '}') return ++pos_, true;
    for (;;) {
      SkipSpace();
      std::string key;
      if (Peek() != '"' || !String(&key)) return false;
      SkipSpace();
      if (Peek() != ':') return false;
      ++pos_;
      if (!Value(path.empty() ? key : path + "." + key, depth + 1)) return false;
      SkipSpace();
      if (Peek() == ',') {
        ++pos_;
        continue;
      }
      if (Peek() == '}') return ++pos_, true;
      return false;
    }
  }

  bool Array(const std::string& path, int depth) {
    ++pos_;
    SkipSpace();
    if (Peek() == ']') return ++pos_, true;
    for (std::size_t index = 0;; ++index) {
      if (!Value(path + "[" + std::to_string(index) + "]", depth + 1)) return false;
      SkipSpace();
      if (Peek() == ',') {
        ++pos_;
        continue;
      }
      if (Peek() == ']') return ++pos_, true;
      return false;
    }
  }

  bool String(std::string* out) {
    ++pos_;  // opening quote
    const std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '"') pos_ += text_[pos_] == '\\' ? 2 : 1;
    if (pos_ >= text_.size()) return false;
    if (out != nullptr) out->assign(text_.substr(start, pos_ - start));
    ++pos_;
    return true;
  }

  void SkipSpace() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' ||
                                   text_[pos_] == '\r' || text_[pos_] == '\n')) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }

  char Peek() const { return pos_ < text_.size() ? text_[pos_] : '\0'; }

  std::string_view text_;
  std::string_view target_;
  bool scalar_token_ = false;
  std::string found_path_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
  std::size_t found_line_ = 0;
};

}  // namespace

std::size_t JsonValueLine(std::string_view text, std::string_view path) {
  return Locator(text, path, false).Find();
}

std::optional<JsonScalarHit> FindJsonScalar(std::string_view text, std::string_view token) {
  Locator locator(text, token, true);
  const std::size_t line = locator.Find();
  if (line == 0) return std::nullopt;
  return JsonScalarHit{line, locator.found_path()};
}

std::size_t LineOfOffset(std::string_view text, std::size_t offset) {
  const std::size_t end = std::min(offset, text.size());
  return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + end, '\n'));
}

}  // namespace hrgbench::session::internal
