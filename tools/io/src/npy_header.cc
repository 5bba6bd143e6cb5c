#include "npy_header.h"

#include <cctype>
#include <limits>

#include "tlvlink/io/npy.h"

namespace tlvlink::tools {
namespace {

// Largest single dimension accepted; the product is limited separately by kMaxNpyDataBytes.
constexpr int64_t kMaxDim = int64_t{1} << 31;

class Parser {
 public:
  Parser(std::string_view text, const std::string& name) : s_(text), name_(name) {}

  Result<NpyHeader> parse() {
    NpyHeader h;
    bool have_descr = false, have_order = false, have_shape = false;
    skip_space();
    TLV_TRY(expect('{'));
    for (;;) {
      skip_space();
      if (peek() == '}') {
        ++pos_;
        break;
      }
      TLV_ASSIGN_OR_RETURN(std::string key, string_literal());
      skip_space();
      TLV_TRY(expect(':'));
      skip_space();
      if (key == "descr") {
        TLV_ENSURE(!have_descr, ErrorCode::kFormat, "%s: header repeats 'descr'", name_.c_str());
        TLV_ASSIGN_OR_RETURN(h.descr, string_literal());
        have_descr = true;
      } else if (key == "fortran_order") {
        TLV_ENSURE(!have_order, ErrorCode::kFormat, "%s: header repeats 'fortran_order'",
                   name_.c_str());
        TLV_ASSIGN_OR_RETURN(h.fortran_order, boolean());
        have_order = true;
      } else if (key == "shape") {
        TLV_ENSURE(!have_shape, ErrorCode::kFormat, "%s: header repeats 'shape'", name_.c_str());
        TLV_ASSIGN_OR_RETURN(h.shape, tuple());
        have_shape = true;
      } else {
        return Error::make(ErrorCode::kFormat, "%s: header has unknown key '%s'", name_.c_str(),
                           key.c_str());
      }
      skip_space();
      if (peek() == ',') {
        ++pos_;
        continue;
      }
      skip_space();
      TLV_ENSURE(peek() == '}', ErrorCode::kFormat, "%s: header: expected ',' or '}' at offset %zu",
                 name_.c_str(), pos_);
    }
    skip_space();
    TLV_ENSURE(pos_ == s_.size(), ErrorCode::kFormat,
               "%s: header has text after the dict at offset %zu", name_.c_str(), pos_);
    TLV_ENSURE(have_descr && have_order && have_shape, ErrorCode::kFormat, "%s: header lacks %s",
               name_.c_str(),
               !have_descr   ? "'descr'"
               : !have_order ? "'fortran_order'"
                             : "'shape'");
    return h;
  }

 private:
  char peek() const { return pos_ < s_.size() ? s_[pos_] : '\0'; }
  void skip_space() {
    while (pos_ < s_.size() &&
           (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\n' || s_[pos_] == '\r'))
      ++pos_;
  }
  Status expect(char c) {
    TLV_ENSURE(peek() == c, ErrorCode::kFormat, "%s: header: expected '%c' at offset %zu",
               name_.c_str(), c, pos_);
    ++pos_;
    return {};
  }
  Result<std::string> string_literal() {
    const char quote = peek();
    TLV_ENSURE(quote == '\'' || quote == '"', ErrorCode::kFormat,
               "%s: header: expected a quoted string at offset %zu", name_.c_str(), pos_);
    const size_t end = s_.find(quote, pos_ + 1);
    TLV_ENSURE(end != std::string_view::npos, ErrorCode::kFormat, "%s: header: unterminated string",
               name_.c_str());
    std::string out(s_.substr(pos_ + 1, end - pos_ - 1));
    pos_ = end + 1;
    return out;
  }
  Result<bool> boolean() {
    if (s_.substr(pos_, 4) == "True") {
      pos_ += 4;
      return true;
    }
    if (s_.substr(pos_, 5) == "False") {
      pos_ += 5;
      return false;
    }
    return Error::make(ErrorCode::kFormat, "%s: header: 'fortran_order' must be True or False",
                       name_.c_str());
  }
  Result<std::vector<int64_t>> tuple() {
    std::vector<int64_t> dims;
    TLV_TRY(expect('('));
    for (;;) {
      skip_space();
      if (peek() == ')') {
        ++pos_;
        break;
      }
      TLV_ENSURE(std::isdigit(static_cast<unsigned char>(peek())), ErrorCode::kFormat,
                 "%s: header: shape entry at offset %zu is not a non-negative integer",
                 name_.c_str(), pos_);
      int64_t v = 0;
      while (std::isdigit(static_cast<unsigned char>(peek()))) {
        v = v * 10 + (s_[pos_++] - '0');
        TLV_ENSURE(v <= kMaxDim, ErrorCode::kFormat, "%s: shape dimension %zu exceeds %lld",
                   name_.c_str(), dims.size(), static_cast<long long>(kMaxDim));
      }
      TLV_ENSURE(dims.size() < kMaxNpyRank, ErrorCode::kFormat,
                 "%s: shape has more than %zu dimensions", name_.c_str(), kMaxNpyRank);
      dims.push_back(v);
      skip_space();
      if (peek() == ',') {
        ++pos_;
        continue;
      }
      skip_space();
      TLV_ENSURE(peek() == ')', ErrorCode::kFormat,
                 "%s: header: expected ',' or ')' in shape at offset %zu", name_.c_str(), pos_);
    }
    return dims;
  }

  std::string_view s_;
  const std::string& name_;
  size_t pos_ = 0;
};

}  // namespace

Result<NpyHeader> parse_npy_header_dict(std::string_view text, const std::string& name) {
  return Parser(text, name).parse();
}

std::string format_npy_header_dict(DType dtype, const std::vector<int64_t>& shape) {
  return std::string("{'descr': '") + npy_descr(dtype) +
         "', 'fortran_order': False, 'shape': " + npy_shape_string(shape) + ", }";
}

}  // namespace tlvlink::tools
