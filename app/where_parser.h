#pragma once
// The `--where` language of `napkin query` (docs/formats.md "Query
// filters"): a recursive-descent parser from text to db::WhereExpression.
//
//   expression := conjunction ( "or" conjunction )*
//   conjunction := primary ( "and" primary )*
//   primary    := "(" expression ")" | FIELD OPERATOR VALUE
//   OPERATOR   := "=" | "!=" | "<" | "<=" | ">" | ">="
//   VALUE      := a bare word (no blanks, quotes, parentheses or operator
//                 characters: 700, -1.5e2, foam-a) | "double-quoted text"
//                 (inside, \" is a quote and \\ a backslash)
//
// `and` binds tighter than `or`; keywords are case-insensitive. FIELD must
// be one of `fields`; a numeric field takes a number (a bare word that reads
// as a finite decimal number), a text field takes the value's text.
#include <string_view>
#include <vector>

#include "app/request_options.h"
#include "db/catalogue.h"
#include "db/where_expression.h"

namespace napkin::app {

// Throws UsageError, one line naming the offending token (and its column)
// and listing `fields`, when `text` is malformed, names a field not in
// `fields`, gives a numeric field a value that is not a number, nests
// parentheses deeper than db::kMaxWhereNesting or holds more than
// db::kMaxWhereComparisons comparisons. The expression and its tokens are
// quoted cut (util::Abbreviated); the option is named as `front_end` spells it
// ("--where", "parameter 'where'", "argument 'where'").
db::WhereExpression ParseWhereExpression(std::string_view text, const std::vector<db::QueryField>& fields,
                                         FrontEnd front_end = FrontEnd::kCommandLine);

}  // namespace napkin::app
