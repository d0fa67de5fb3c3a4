#include "app/where_parser.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <system_error>

#include "common/error.h"
#include "util/text.h"

namespace napkin::app {
namespace {

struct Token {
  enum class Kind { kWord, kString, kOperator, kLeftParenthesis, kRightParenthesis, kEnd };
  Kind kind = Kind::kEnd;
  std::string text;   // as typed (a string with its quotes)
  std::string value;  // a word's text, a string's unescaped text
  db::ComparisonOperator op = db::ComparisonOperator::kEqual;
  std::size_t column = 0;  // 1-based position of its first character
};

bool EndsWord(char c) {
  return std::isspace(static_cast<unsigned char>(c)) || c == '"' || c == '\'' || c == '(' || c == ')' ||
         c == '=' || c == '!' || c == '<' || c == '>';
}

class Parser {
 public:
  Parser(std::string_view text, const std::vector<db::QueryField>& fields, FrontEnd front_end)
      : text_(text), fields_(fields), front_end_(front_end) {}

  db::WhereExpression Parse() {
    Tokenize();
    if (tokens_.front().kind == Token::Kind::kEnd) Fail("the expression is empty");
    db::WhereExpression expression = Disjunction();
    if (Peek().kind != Token::Kind::kEnd)
      Fail("expected 'and', 'or' or the end of the expression " + Found(Peek()));
    return expression;
  }

 private:
  // The expression is quoted cut to its first 60 bytes, as all quoted input
  // (docs/formats.md "Names, limits and escaping"); the column finds the rest.
  [[noreturn]] void Fail(const std::string& problem) const {
    std::string shown(text_);
    std::replace_if(
        shown.begin(), shown.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
    throw UsageError(OptionName(front_end_, "where") + " \"" + util::Abbreviated(shown) + "\": " + problem +
                     "; the fields are " + db::FieldNames(fields_) + ".");
  }

  // A token's text as typed, cut like the expression.
  static std::string Shown(const Token& token) { return util::Abbreviated(token.text); }

  // "at column N, found 'X'" (or "found the end").
  static std::string Found(const Token& token) {
    if (token.kind == Token::Kind::kEnd)
      return "at column " + std::to_string(token.column) + ", found the end";
    // Appended, not `"'" + temporary` (GCC 12's false -Wrestrict, util/text.h InQuotes).
    const std::string shown =
        token.kind == Token::Kind::kString ? Shown(token) : std::string("'").append(Shown(token)).append("'");
    return "at column " + std::to_string(token.column) + ", found " + shown;
  }

  void Tokenize() {
    std::size_t i = 0;
    while (true) {
      while (i < text_.size() && std::isspace(static_cast<unsigned char>(text_[i]))) ++i;
      Token token;
      token.column = i + 1;
      if (i == text_.size()) {
        tokens_.push_back(token);
        return;
      }
      const char c = text_[i];
      if (c == '(' || c == ')') {
        token.kind = c == '(' ? Token::Kind::kLeftParenthesis : Token::Kind::kRightParenthesis;
        token.text = std::string(1, c);
        ++i;
      } else if (c == '=' || c == '!' || c == '<' || c == '>') {
        const bool equals_follows = i + 1 < text_.size() && text_[i + 1] == '=';
        if (c == '!' && !equals_follows)
          Fail("'!' at column " + std::to_string(token.column) + " is not an operator (not equal is !=)");
        token.kind = Token::Kind::kOperator;
        token.text = text_.substr(i, c != '=' && equals_follows ? 2 : 1);
        using Op = db::ComparisonOperator;
        token.op = c == '='   ? Op::kEqual
                   : c == '!' ? Op::kNotEqual
                   : c == '<' ? (equals_follows ? Op::kLessEqual : Op::kLess)
                              : (equals_follows ? Op::kGreaterEqual : Op::kGreater);
        i += token.text.size();
      } else if (c == '\'') {
        Fail("single quote at column " + std::to_string(token.column) +
             ": write text values in double quotes (\"like this\")");
      } else if (c == '"') {
        token.kind = Token::Kind::kString;
        std::size_t j = i + 1;
        for (;; ++j) {
          if (j == text_.size())
            Fail("the text value starting at column " + std::to_string(token.column) +
                 " has no closing '\"'");
          if (text_[j] == '"') break;
          if (text_[j] == '\\') {
            if (j + 1 == text_.size() || (text_[j + 1] != '"' && text_[j + 1] != '\\'))
              Fail("unknown escape at column " + std::to_string(j + 1) +
                   " (inside double quotes, \\\" is a quote and \\\\ a backslash)");
            ++j;
          }
          token.value += text_[j];
        }
        token.text = text_.substr(i, j + 1 - i);
        i = j + 1;
      } else {
        token.kind = Token::Kind::kWord;
        std::size_t j = i;
        while (j < text_.size() && !EndsWord(text_[j])) ++j;
        token.text = token.value = text_.substr(i, j - i);
        i = j;
      }
      tokens_.push_back(std::move(token));
    }
  }

  const Token& Peek() const { return tokens_[next_]; }
  const Token& Take() { return tokens_[next_ < tokens_.size() - 1 ? next_++ : next_]; }
  bool IsKeyword(const Token& token, const char* keyword) const {
    return token.kind == Token::Kind::kWord && util::ToLower(token.text) == keyword;
  }

  // Operands joined by `keyword`; one operand stands for itself.
  template <typename Operand>
  db::WhereExpression Junction(db::WhereJunction::Kind kind, const char* keyword, Operand operand) {
    db::WhereJunction junction{kind, {}};
    junction.operands.push_back(operand());
    while (IsKeyword(Peek(), keyword)) {
      Take();
      junction.operands.push_back(operand());
    }
    if (junction.operands.size() == 1) return std::move(junction.operands.front());
    return db::WhereExpression{std::move(junction)};
  }

  db::WhereExpression Disjunction() {
    return Junction(db::WhereJunction::Kind::kOr, "or", [this] { return Conjunction(); });
  }

  db::WhereExpression Conjunction() {
    return Junction(db::WhereJunction::Kind::kAnd, "and", [this] { return Primary(); });
  }

  db::WhereExpression Primary() {
    if (Peek().kind == Token::Kind::kLeftParenthesis) {
      const Token open = Take();
      // The limit keeps the recursion bounded and the SQL within what SQLite parses.
      if (++nesting_ > db::kMaxWhereNesting)
        Fail("the '(' at column " + std::to_string(open.column) + " nests parentheses deeper than " +
             std::to_string(db::kMaxWhereNesting) + " levels");
      db::WhereExpression inner = Disjunction();
      if (Peek().kind == Token::Kind::kEnd)
        Fail("the '(' at column " + std::to_string(open.column) +
             " is never closed (the expression ends at column " + std::to_string(Peek().column) + ")");
      if (Peek().kind != Token::Kind::kRightParenthesis) Fail("expected 'and', 'or' or ')' " + Found(Peek()));
      Take();
      --nesting_;
      return inner;
    }
    return Comparison();
  }

  db::WhereExpression Comparison() {
    const Token field_token = Take();
    if (field_token.kind != Token::Kind::kWord || IsKeyword(field_token, "and") ||
        IsKeyword(field_token, "or"))
      Fail("expected a field name " + Found(field_token));
    if (++comparisons_ > db::kMaxWhereComparisons)
      Fail("the comparison at column " + std::to_string(field_token.column) + " is one more than the " +
           std::to_string(db::kMaxWhereComparisons) + " an expression may hold");
    const auto field = std::find_if(fields_.begin(), fields_.end(),
                                    [&](const db::QueryField& f) { return f.name == field_token.text; });
    if (field == fields_.end())
      Fail("unknown field '" + Shown(field_token) + "' at column " + std::to_string(field_token.column));

    const Token op = Take();
    if (op.kind != Token::Kind::kOperator)
      Fail("expected an operator (= != < <= > >=) after '" + Shown(field_token) + "' " + Found(op));
    const Token value = Take();
    if (value.kind != Token::Kind::kWord && value.kind != Token::Kind::kString)
      Fail("expected a value after '" + op.text + "' " + Found(value));

    db::WhereComparison comparison{field->name, op.op, value.value};
    if (field->numeric) {
      const std::optional<double> number =
          value.kind == Token::Kind::kWord ? Number(value.value) : std::nullopt;
      if (!number)
        Fail("field '" + field->name + "' holds numbers, but " +
             (value.kind == Token::Kind::kString ? Shown(value)
                                                 : std::string("'").append(Shown(value)).append("'")) +
             " at column " + std::to_string(value.column) + " is not a number");
      comparison.value = *number;
    }
    return db::WhereExpression{std::move(comparison)};
  }

  // The word as a finite decimal number, if all of it reads as one.
  static std::optional<double> Number(const std::string& word) {
    if (word.size() > 1 && word[0] == '+' && (word[1] == '+' || word[1] == '-')) return std::nullopt;
    const char* begin = word.data() + (word.size() > 1 && word[0] == '+' ? 1 : 0);
    const char* end = word.data() + word.size();
    double number = 0.0;
    const auto [stop, error] = std::from_chars(begin, end, number, std::chars_format::general);
    if (error != std::errc() || stop != end || !std::isfinite(number)) return std::nullopt;
    return number;
  }

  std::string text_;
  const std::vector<db::QueryField>& fields_;
  FrontEnd front_end_;
  std::vector<Token> tokens_;
  std::size_t next_ = 0;
  int nesting_ = 0;              // parentheses open at the current token
  std::size_t comparisons_ = 0;  // comparisons read so far
};

}  // namespace

db::WhereExpression ParseWhereExpression(std::string_view text, const std::vector<db::QueryField>& fields,
                                         FrontEnd front_end) {
  return Parser(text, fields, front_end).Parse();
}

}  // namespace napkin::app
