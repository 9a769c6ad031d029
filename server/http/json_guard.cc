// SPDX-License-Identifier: Apache-2.0
#include "server/http/json_guard.h"

#include <cstdint>
#include <string>
#include <vector>

#include "absl/container/flat_hash_set.h"
#include "absl/strings/ascii.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"

namespace ispq::server::http {
namespace {

// Objects with more keys than this look their keys up in a hash set instead of a list.
constexpr size_t kFewKeys = 16;

absl::Status Refused(absl::string_view what, size_t offset) {
  return absl::InvalidArgumentError(absl::StrCat("the body ", what, " (at byte ", offset, ")"));
}

// The length of the UTF-8 sequence starting at `at` (1 to 4), or 0 if it is no valid one.
size_t Utf8SequenceLength(absl::string_view text, size_t at) {
  const auto byte = [&](size_t i) { return static_cast<uint8_t>(text[i]); };
  const uint8_t lead = byte(at);
  if (lead < 0x80) return 1;
  size_t length = 0;
  uint8_t low = 0x80;  // the second byte's range: excludes overlong forms and surrogates
  uint8_t high = 0xBF;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;
    if (lead == 0xED) high = 0x9F;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;
    if (lead == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (at + length > text.size() || byte(at + 1) < low || byte(at + 1) > high) return 0;
  for (size_t i = 2; i < length; ++i) {
    if (byte(at + i) < 0x80 || byte(at + i) > 0xBF) return 0;
  }
  return length;
}

absl::Status CheckEncoding(absl::string_view body) {
  if (body.substr(0, 3) == "\xEF\xBB\xBF") {
    return absl::InvalidArgumentError("the body starts with a byte order mark: send plain UTF-8");
  }
  for (size_t at = 0; at < body.size();) {
    if (body[at] == '\0') return Refused("contains a NUL byte", at);
    const size_t length = Utf8SequenceLength(body, at);
    if (length == 0) return Refused("is not valid UTF-8", at);
    at += length;
  }
  return absl::OkStatus();
}

void AppendUtf8(uint32_t code_point, std::string& out) {
  if (code_point < 0x80) {
    out.push_back(static_cast<char>(code_point));
  } else if (code_point < 0x800) {
    out.push_back(static_cast<char>(0xC0 | (code_point >> 6)));
    out.push_back(static_cast<char>(0x80 | (code_point & 0x3F)));
  } else if (code_point < 0x10000) {
    out.push_back(static_cast<char>(0xE0 | (code_point >> 12)));
    out.push_back(static_cast<char>(0x80 | ((code_point >> 6) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | (code_point & 0x3F)));
  } else {
    out.push_back(static_cast<char>(0xF0 | (code_point >> 18)));
    out.push_back(static_cast<char>(0x80 | ((code_point >> 12) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | ((code_point >> 6) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | (code_point & 0x3F)));
  }
}

// The four hex digits at `at` as a number, or -1.
int64_t HexQuad(absl::string_view text, size_t at) {
  uint32_t value = 0;
  if (at + 4 > text.size() || !absl::SimpleHexAtoi(text.substr(at, 4), &value)) return -1;
  for (size_t i = at; i < at + 4; ++i) {
    if (!absl::ascii_isxdigit(static_cast<unsigned char>(text[i]))) return -1;
  }
  return value;
}

// The text of a JSON string's contents with its escapes decoded (as the parser sees the key);
// malformed escapes are kept as they are, for the parser to refuse.
std::string Unescape(absl::string_view raw) {
  std::string out;
  out.reserve(raw.size());
  for (size_t i = 0; i < raw.size(); ++i) {
    if (raw[i] != '\\' || i + 1 == raw.size()) {
      out.push_back(raw[i]);
      continue;
    }
    const char escaped = raw[++i];
    switch (escaped) {
      case 'b':
        out.push_back('\b');
        break;
      case 'f':
        out.push_back('\f');
        break;
      case 'n':
        out.push_back('\n');
        break;
      case 'r':
        out.push_back('\r');
        break;
      case 't':
        out.push_back('\t');
        break;
      case 'u': {
        int64_t code = HexQuad(raw, i + 1);
        if (code < 0) {
          out.append("\\u");
          break;
        }
        i += 4;
        const int64_t low = raw.substr(i + 1, 2) == "\\u" ? HexQuad(raw, i + 3) : -1;
        if (code >= 0xD800 && code <= 0xDBFF && low >= 0xDC00 && low <= 0xDFFF) {
          code = 0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00);
          i += 6;
        }
        AppendUtf8(static_cast<uint32_t>(code), out);
        break;
      }
      default:
        out.push_back(escaped);  // \" \\ \/ and anything the parser will refuse
    }
  }
  return out;
}

// A key as protobuf's JSON parser matches it to a field: the lowerCamelCase JSON name, which
// both "stored_mesh" and "storedMesh" map to.
std::string FieldKey(std::string key) {
  if (key.find('_') == std::string::npos) return key;
  std::string camel;
  camel.reserve(key.size());
  bool upper = false;
  for (const char c : key) {
    if (c == '_') {
      upper = true;
      continue;
    }
    camel.push_back(upper ? absl::ascii_toupper(static_cast<unsigned char>(c)) : c);
    upper = false;
  }
  return camel;
}

// The keys seen so far in one open object.
class KeySet {
 public:
  void Clear() {
    few_.clear();
    many_.clear();
  }
  // False if `key` was there already.
  bool Insert(std::string key) {
    if (!many_.empty()) return many_.insert(std::move(key)).second;
    for (const std::string& seen : few_) {
      if (seen == key) return false;
    }
    few_.push_back(std::move(key));
    if (few_.size() > kFewKeys) {
      many_.insert(few_.begin(), few_.end());
      few_.clear();
    }
    return true;
  }

 private:
  std::vector<std::string> few_;
  absl::flat_hash_set<std::string> many_;
};

struct Level {
  bool object = false;
  bool expecting_key = false;
  KeySet keys;
};

// The end of the string whose opening quote is at `open`: the index of its closing quote, or
// npos if it does not end.
size_t StringEnd(absl::string_view body, size_t open) {
  for (size_t i = open + 1; i < body.size(); ++i) {
    if (body[i] == '\\') {
      ++i;
    } else if (body[i] == '"') {
      return i;
    }
  }
  return absl::string_view::npos;
}

class StructureCheck {
 public:
  explicit StructureCheck(int max_depth) : max_depth_(max_depth) {}

  absl::Status Run(absl::string_view body) {
    for (size_t at = 0; at < body.size(); ++at) {
      switch (body[at]) {
        case '"': {
          const size_t end = StringEnd(body, at);
          if (end == absl::string_view::npos) return absl::OkStatus();  // the parser says so
          if (absl::Status key = Key(body.substr(at + 1, end - at - 1), at); !key.ok()) return key;
          at = end;
          break;
        }
        case '{':
        case '[':
          if (absl::Status opened = Open(body[at] == '{', at); !opened.ok()) return opened;
          break;
        case '}':
        case ']':
          if (depth_ == 0) return absl::OkStatus();  // unbalanced: the parser says so
          --depth_;
          break;
        case ',':
          if (depth_ > 0 && levels_[depth_ - 1].object) levels_[depth_ - 1].expecting_key = true;
          break;
        default:
          break;
      }
    }
    return absl::OkStatus();
  }

 private:
  absl::Status Open(bool object, size_t at) {
    if (depth_ >= max_depth_) {
      return Refused(absl::StrCat("nests objects and arrays deeper than ", max_depth_,
                                  " levels, the most this server accepts"),
                     at);
    }
    if (static_cast<int>(levels_.size()) == depth_) levels_.emplace_back();
    Level& level = levels_[depth_++];
    level.object = object;
    level.expecting_key = object;
    level.keys.Clear();
    return absl::OkStatus();
  }

  absl::Status Key(absl::string_view raw, size_t at) {
    if (depth_ == 0 || !levels_[depth_ - 1].expecting_key) return absl::OkStatus();  // a value
    Level& level = levels_[depth_ - 1];
    level.expecting_key = false;
    std::string key = Unescape(raw);
    if (!level.keys.Insert(FieldKey(key))) {
      return Refused(absl::StrCat("repeats the key \"", key.substr(0, 100), "\" in one object"),
                     at);
    }
    return absl::OkStatus();
  }

  const int max_depth_;
  int depth_ = 0;
  std::vector<Level> levels_;  // levels_[0..depth_) are open; deeper ones kept for reuse
};

}  // namespace

absl::Status CheckJsonBody(absl::string_view body, int max_depth) {
  if (absl::Status encoding = CheckEncoding(body); !encoding.ok()) return encoding;
  return StructureCheck(max_depth).Run(body);
}

}  // namespace ispq::server::http
