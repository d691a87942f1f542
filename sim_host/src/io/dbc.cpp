#include "stickslip/host/io/dbc.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <system_error>

#include "dbc_scale.hpp"
#include "stickslip/host/error.hpp"
#include "text_lines.hpp"

namespace stickslip::host {
namespace {

constexpr std::uint32_t kDbcExtendedFlag = 0x80000000u;
constexpr unsigned kMaxFrameBytes = 64;  // CAN FD; a classic frame carries 8

struct Token {
  enum Kind { kIdentifier, kNumber, kString, kPunct, kEnd } kind = kEnd;
  std::string_view text;  // a string token without its quotes
  std::size_t line = 0;
  bool first_on_line = false;  // no other token before it on its line
  bool indented = false;       // its line starts with a blank
};

bool identifier_start(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_';
}
bool digit(char c) {
  return c >= '0' && c <= '9';
}

class Lexer {
 public:
  Lexer(std::string_view text, const std::string& path) : text_(text), path_(path) {
    if (text_.size() >= 3 && text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);
  }

  Token next() {
    Token token;
    bool new_line = last_line_ != line_;
    for (;;) {
      while (at_ < text_.size() && (text::is_space(text_[at_]) || text_[at_] == '\n')) {
        if (text_[at_] == '\n') {
          ++line_;
          new_line = true;
          line_start_ = at_ + 1;
        }
        ++at_;
      }
      // "//" comments run to the end of the line (some tools write them).
      if (at_ + 1 < text_.size() && text_[at_] == '/' && text_[at_ + 1] == '/') {
        while (at_ < text_.size() && text_[at_] != '\n') ++at_;
        continue;
      }
      break;
    }
    token.line = line_;
    token.first_on_line = new_line || last_line_ == 0;
    token.indented = line_start_ < text_.size() && text::is_space(text_[line_start_]);
    if (at_ >= text_.size()) {
      token.kind = Token::kEnd;
      return token;
    }
    const std::size_t start = at_;
    const char c = text_[at_];
    if (c == '"') {
      ++at_;
      const std::size_t body = at_;
      while (at_ < text_.size() && text_[at_] != '"') {
        if (text_[at_] == '\\' && at_ + 1 < text_.size()) ++at_;
        if (text_[at_] == '\n') ++line_;
        ++at_;
      }
      if (at_ >= text_.size()) text::fail(path_, token.line, "string not closed by '\"'");
      token.kind = Token::kString;
      token.text = text_.substr(body, at_ - body);
      ++at_;
    } else if (identifier_start(c)) {
      while (at_ < text_.size() && (identifier_start(text_[at_]) || digit(text_[at_]))) ++at_;
      token.kind = Token::kIdentifier;
      token.text = text_.substr(start, at_ - start);
    } else if (digit(c) || ((c == '-' || c == '+' || c == '.') && at_ + 1 < text_.size() &&
                            (digit(text_[at_ + 1]) || text_[at_ + 1] == '.'))) {
      ++at_;
      while (at_ < text_.size() && (digit(text_[at_]) || text_[at_] == '.')) ++at_;
      if (at_ < text_.size() && (text_[at_] == 'e' || text_[at_] == 'E')) {
        std::size_t look = at_ + 1;
        if (look < text_.size() && (text_[look] == '-' || text_[look] == '+')) ++look;
        if (look < text_.size() && digit(text_[look])) {
          at_ = look;
          while (at_ < text_.size() && digit(text_[at_])) ++at_;
        }
      }
      token.kind = Token::kNumber;
      token.text = text_.substr(start, at_ - start);
    } else {
      ++at_;
      token.kind = Token::kPunct;
      token.text = text_.substr(start, 1);
    }
    last_line_ = line_;
    return token;
  }

 private:
  std::string_view text_;
  const std::string& path_;
  std::size_t at_ = 0;
  std::size_t line_ = 1;
  std::size_t last_line_ = 0;
  std::size_t line_start_ = 0;
};

class Parser {
 public:
  Parser(std::string_view text, const std::string& path) : lexer_(text, path), path_(path) {
    advance();
  }

  Dbc parse() {
    Dbc dbc;
    dbc.path = path_;
    while (token_.kind != Token::kEnd) {
      if (!token_.first_on_line || token_.kind != Token::kIdentifier) {
        advance();
        continue;
      }
      const std::string_view keyword = token_.text;
      if (keyword == "BO_") {
        parse_message(dbc);
      } else if (keyword == "SG_") {
        if (dbc.messages.empty()) fail("SG_ before any BO_ (a signal belongs to a message)");
        parse_signal(dbc.messages.back());
      } else if (keyword == "CM_") {
        parse_comment(dbc);
      } else if (keyword == "VAL_") {
        parse_value_table(dbc);
      } else if (keyword == "SIG_VALTYPE_") {
        fail("SIG_VALTYPE_: IEEE float signals are not supported");
      } else if (keyword == "SG_MUL_VAL_") {
        fail("SG_MUL_VAL_: multiplexed signals are not supported");
      } else if (keyword == "NS_") {
        advance();
        while (token_.kind != Token::kEnd && !(token_.first_on_line && !token_.indented)) advance();
      } else {
        skip_statement();
      }
    }
    return dbc;
  }

 private:
  void advance() { token_ = lexer_.next(); }
  [[noreturn]] void fail(const std::string& what) const { text::fail(path_, token_.line, what); }
  void skip_statement() {
    advance();
    while (token_.kind != Token::kEnd && !token_.first_on_line) advance();
  }
  std::string describe() const {
    if (token_.kind == Token::kEnd) return "the end of the file";
    if (token_.kind == Token::kString) return "a string";
    return text::quoted(token_.text);
  }
  void expect(const char* punct) {
    if (token_.kind != Token::kPunct || token_.text != punct)
      fail(std::string("expected '") + punct + "', found " + describe());
    advance();
  }
  std::string_view identifier(const char* what) {
    if (token_.kind != Token::kIdentifier)
      fail(std::string("expected ") + what + ", found " + describe());
    const std::string_view text = token_.text;
    advance();
    return text;
  }
  std::string_view number_text(const char* what) {
    if (token_.kind != Token::kNumber)
      fail(std::string("expected ") + what + ", found " + describe());
    const std::string_view text = token_.text;
    advance();
    return text;
  }
  double real(const char* what) {
    const std::string_view text = number_text(what);
    std::string_view digits = text;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    double value = 0.0;
    const auto result = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (result.ec != std::errc() || result.ptr != digits.data() + digits.size() ||
        !std::isfinite(value)) {
      text::fail(path_, token_.line,
                 std::string(what) + " " + text::quoted(text) + " is not a finite number");
    }
    return value;
  }
  std::uint64_t unsigned_integer(const char* what, std::uint64_t max) {
    const std::size_t line = token_.line;
    const std::string_view text = number_text(what);
    std::uint64_t value = 0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (result.ec != std::errc() || result.ptr != text.data() + text.size() || value > max)
      text::fail(path_, line,
                 std::string(what) + " " + text::quoted(text) + " is not an integer 0.." +
                     std::to_string(max));
    return value;
  }
  std::int64_t signed_integer(const char* what) {
    const std::size_t line = token_.line;
    const std::string_view text = number_text(what);
    std::string_view digits = text;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    std::int64_t value = 0;
    const auto result = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (result.ec != std::errc() || result.ptr != digits.data() + digits.size())
      text::fail(path_, line, std::string(what) + " " + text::quoted(text) + " is not an integer");
    return value;
  }
  void set_id(std::uint64_t dbc_id, std::uint32_t& id, bool& extended, std::size_t line) {
    extended = (dbc_id & kDbcExtendedFlag) != 0;
    id = static_cast<std::uint32_t>(dbc_id & ~std::uint64_t{kDbcExtendedFlag});
    if (extended ? id > 0x1FFFFFFFu : id > 0x7FFu) {
      text::fail(path_, line,
                 "message id " + std::to_string(dbc_id) + " is beyond " +
                     (extended ? "29 bits" : "11 bits (extended ids set bit 31)"));
    }
  }

  void parse_message(Dbc& dbc) {
    DbcMessage message;
    message.line = token_.line;
    advance();
    const std::uint64_t dbc_id = unsigned_integer("message id", 0xFFFFFFFFu);
    set_id(dbc_id, message.id, message.extended, message.line);
    message.name = identifier("message name");
    expect(":");
    message.dlc = static_cast<unsigned>(unsigned_integer("message length", kMaxFrameBytes));
    if (token_.kind == Token::kIdentifier && !token_.first_on_line)
      message.sender = identifier("sender");
    for (const DbcMessage& seen : dbc.messages) {
      if (seen.id == message.id && seen.extended == message.extended)
        text::fail(path_, message.line,
                   "message id " + std::to_string(dbc_id) + " is already '" + seen.name + "'");
    }
    dbc.messages.push_back(std::move(message));
  }

  void parse_signal(DbcMessage& message) {
    DbcSignal signal;
    signal.line = token_.line;
    advance();
    signal.name = identifier("signal name");
    if (!(token_.kind == Token::kPunct && token_.text == ":")) {
      if (token_.kind == Token::kIdentifier || token_.kind == Token::kNumber) {
        text::fail(path_, signal.line,
                   "signal '" + signal.name + "' of message '" + message.name +
                       "' is multiplexed (" + text::quoted(token_.text) +
                       "); multiplexed signals are not supported");
      }
      expect(":");
    }
    advance();
    signal.start_bit = static_cast<unsigned>(unsigned_integer("start bit", kMaxFrameBytes * 8 - 1));
    expect("|");
    signal.length_bits = static_cast<unsigned>(unsigned_integer("signal length", 64));
    if (signal.length_bits == 0)
      text::fail(path_, signal.line, "signal '" + signal.name + "' has length 0");
    expect("@");
    // "@1+" lexes as the number 1 then '+'; "@0-" as 0 then '-'.
    const std::uint64_t order = unsigned_integer("byte order (0 or 1)", 1);
    signal.byte_order = order == 1 ? ByteOrder::kIntel : ByteOrder::kMotorola;
    if (token_.kind == Token::kPunct && (token_.text == "+" || token_.text == "-")) {
      signal.is_signed = token_.text == "-";
      advance();
    } else {
      fail("expected '+' (unsigned) or '-' (signed) after the byte order, found " + describe());
    }
    expect("(");
    const std::string_view factor_text = token_.text;
    const double factor = real("factor");
    expect(",");
    const std::string_view offset_text = token_.text;
    const double offset = real("offset");
    expect(")");
    signal.scale = make_scale(factor_text, offset_text, factor, offset);
    expect("[");
    signal.minimum = real("minimum");
    expect("|");
    signal.maximum = real("maximum");
    expect("]");
    if (token_.kind != Token::kString)
      fail("expected the unit as a \"string\", found " + describe());
    // A unit is a word on the signal's line; one that runs on is a quote left open, which would
    // swallow the signals after it up to the next quote.
    if (token_.text.find_first_of("\r\n") != std::string_view::npos)
      fail("the unit string is not closed on its line (a '\"' is missing)");
    signal.unit = std::string(token_.text);
    advance();
    while (token_.kind != Token::kEnd && !token_.first_on_line) {
      if (token_.kind == Token::kIdentifier) signal.receivers.emplace_back(token_.text);
      advance();
    }
    // Where the bits are: every one must lie in a frame of at most 64 bytes.
    unsigned position = signal.start_bit;
    unsigned highest_byte = 0;
    for (unsigned n = 0; n < signal.length_bits; ++n) {
      if (position >= kMaxFrameBytes * 8) {
        text::fail(path_, signal.line,
                   "signal '" + signal.name + "' (start bit " + std::to_string(signal.start_bit) +
                       ", " + std::to_string(signal.length_bits) +
                       " bits) runs beyond a 64-byte frame");
      }
      highest_byte = std::max(highest_byte, position / 8);
      if (n + 1 == signal.length_bits) break;
      if (signal.byte_order == ByteOrder::kIntel) {
        ++position;
      } else {
        position = position % 8 == 0 ? position + 15 : position - 1;
      }
    }
    signal.bytes_needed = highest_byte + 1;
    for (const DbcSignal& seen : message.signals)
      if (seen.name == signal.name)
        text::fail(path_, signal.line,
                   "signal '" + signal.name + "' appears twice in message '" + message.name + "'");
    message.signals.push_back(std::move(signal));
  }

  DbcMessage* message_by_dbc_id(std::uint64_t dbc_id, Dbc& dbc) {
    for (DbcMessage& message : dbc.messages)
      if (message.id == (dbc_id & ~std::uint64_t{kDbcExtendedFlag}) &&
          message.extended == ((dbc_id & kDbcExtendedFlag) != 0))
        return &message;
    return nullptr;
  }

  void end_statement() {
    while (token_.kind != Token::kEnd && !(token_.kind == Token::kPunct && token_.text == ";"))
      advance();
    if (token_.kind != Token::kEnd) advance();
  }

  void parse_comment(Dbc& dbc) {
    const std::size_t line = token_.line;
    advance();
    std::string* target = nullptr;
    if (token_.kind == Token::kIdentifier && token_.text == "BO_") {
      advance();
      const std::uint64_t dbc_id = unsigned_integer("message id", 0xFFFFFFFFu);
      DbcMessage* message = message_by_dbc_id(dbc_id, dbc);
      if (message == nullptr)
        text::fail(path_, line, "CM_ BO_ " + std::to_string(dbc_id) + ": no such message");
      target = &message->comment;
    } else if (token_.kind == Token::kIdentifier && token_.text == "SG_") {
      advance();
      const std::uint64_t dbc_id = unsigned_integer("message id", 0xFFFFFFFFu);
      const std::string_view name = identifier("signal name");
      DbcMessage* message = message_by_dbc_id(dbc_id, dbc);
      if (message == nullptr)
        text::fail(path_, line, "CM_ SG_ " + std::to_string(dbc_id) + ": no such message");
      for (DbcSignal& signal : message->signals)
        if (signal.name == name) target = &signal.comment;
      if (target == nullptr)
        text::fail(
            path_, line,
            "CM_ SG_: message '" + message->name + "' has no signal '" + std::string(name) + "'");
    }
    while (token_.kind != Token::kEnd && token_.kind != Token::kString &&
           !(token_.kind == Token::kPunct && token_.text == ";"))
      advance();
    if (token_.kind == Token::kString && target != nullptr) *target = std::string(token_.text);
    end_statement();
  }

  void parse_value_table(Dbc& dbc) {
    const std::size_t line = token_.line;
    advance();
    if (token_.kind != Token::kNumber) {  // a table of an environment variable
      end_statement();
      return;
    }
    const std::uint64_t dbc_id = unsigned_integer("message id", 0xFFFFFFFFu);
    const std::string_view name = identifier("signal name");
    DbcMessage* message = message_by_dbc_id(dbc_id, dbc);
    if (message == nullptr)
      text::fail(path_, line, "VAL_ " + std::to_string(dbc_id) + ": no such message");
    DbcSignal* signal = nullptr;
    for (DbcSignal& candidate : message->signals)
      if (candidate.name == name) signal = &candidate;
    if (signal == nullptr)
      text::fail(path_, line,
                 "VAL_: message '" + message->name + "' has no signal '" + std::string(name) + "'");
    signal->value_names.clear();
    while (token_.kind == Token::kNumber) {
      const std::int64_t value = signed_integer("value");
      if (token_.kind != Token::kString)
        fail("expected the value's \"description\", found " + describe());
      signal->value_names.emplace_back(value, std::string(token_.text));
      advance();
    }
    expect(";");
  }

  Lexer lexer_;
  const std::string& path_;
  Token token_;
};

}  // namespace

const DbcSignal* DbcMessage::find_signal(std::string_view wanted) const {
  for (const DbcSignal& signal : signals)
    if (signal.name == wanted) return &signal;
  return nullptr;
}

const DbcMessage* Dbc::find_message(std::string_view wanted) const {
  for (const DbcMessage& message : messages)
    if (message.name == wanted) return &message;
  return nullptr;
}

const DbcMessage* Dbc::find_message(std::uint32_t id, bool extended) const {
  for (const DbcMessage& message : messages)
    if (message.id == id && message.extended == extended) return &message;
  return nullptr;
}

Dbc parse_dbc(std::string_view text, const std::string& path) {
  return Parser(text, path).parse();
}

Dbc read_dbc(const std::string& path) {
  const std::string bytes = text::read_file(path);
  return parse_dbc(bytes, path);
}

std::optional<std::int64_t> raw_value(const DbcSignal& signal, const std::uint8_t* data,
                                      std::size_t length) noexcept {
  if (length < signal.bytes_needed) return std::nullopt;
  std::uint64_t raw = 0;
  unsigned position = signal.start_bit;
  for (unsigned n = 0; n < signal.length_bits; ++n) {
    const std::uint64_t bit = (data[position / 8] >> (position % 8)) & 1u;
    if (signal.byte_order == ByteOrder::kIntel) {
      raw |= bit << n;
      ++position;
    } else {
      raw = (raw << 1) | bit;  // most significant bit first
      position = position % 8 == 0 ? position + 15 : position - 1;
    }
  }
  if (signal.is_signed && signal.length_bits < 64 && ((raw >> (signal.length_bits - 1)) & 1u) != 0)
    raw |= ~std::uint64_t{0} << signal.length_bits;
  std::int64_t value = 0;
  std::memcpy(&value, &raw, sizeof value);  // two's complement, without a narrowing conversion
  return value;
}

double physical_value(const DbcSignal& signal, std::int64_t raw) noexcept {
  const DbcScale& scale = signal.scale;
  constexpr std::int64_t kExactInDouble = std::int64_t{1} << 53;
  if (scale.exact && (signal.is_signed || raw >= 0)) {
    std::int64_t numerator = 0;
    if (!__builtin_mul_overflow(raw, scale.numerator_per_raw, &numerator) &&
        !__builtin_add_overflow(numerator, scale.numerator_offset, &numerator) &&
        numerator < kExactInDouble && numerator > -kExactInDouble) {
      return static_cast<double>(numerator) / scale.denominator;
    }
  }
  const double value = signal.is_signed ? static_cast<double>(raw)
                                        : static_cast<double>(static_cast<std::uint64_t>(raw));
  return value * scale.factor + scale.offset;
}

std::optional<double> decode_signal(const DbcSignal& signal, const std::uint8_t* data,
                                    std::size_t length) noexcept {
  const std::optional<std::int64_t> raw = raw_value(signal, data, length);
  if (!raw) return std::nullopt;
  return physical_value(signal, *raw);
}

}  // namespace stickslip::host
