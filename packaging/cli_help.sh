# shellcheck shell=bash
# Sourced by man_sections.sh and bash_completion.sh: napkin's subcommands and options as CLI11
# prints them in --help. The layout read (CLI11 2.3, Debian libcli11-dev): section headings
# ("Options:", "Subcommands:") start in column 1; an entry starts with two spaces, its names (and
# value type, if it takes one) come first, then two or more spaces and the description; a long
# entry's description continues on lines indented further.

# Runs napkin as `napkin` (from PATH) so that its usage lines name it, not the build tree.
napkin_help() {
  PATH="$(dirname "$NAPKIN"):$PATH" napkin "$@" --help
}

# The subcommands, one a line: the entries of the "Subcommands:" section.
napkin_subcommands() {
  napkin_help | awk '/^[A-Za-z].*:$/ { in_section = ($0 == "Subcommands:"); next }
                     in_section && /^  [a-z]/ { print $1 }'
}

# One line per option of `napkin $1` ($1 empty: the top level): "NAMES<TAB>TAKES_VALUE<TAB>VALUES",
# NAMES comma-separated (-q,--quiet), TAKES_VALUE 1 when a value type follows the names, VALUES
# what the value may be: "presets:<config/ folder>" when the description says it names a preset
# ("array preset", "channel map preset", "processing config preset", "limits preset"), "choices:<words>" when the
# type lists them (CLI11's IsMember: "TEXT:one of table, csv or json"), else empty.
napkin_options() {
  napkin_help ${1:+"$1"} | awk '
    function flush() { if (names != "") print names "\t" takes_value "\t" values; names = "" }
    /^  -/ {
      flush()
      entry = substr($0, 3); spec = entry; description = ""
      if (match(entry, /   */)) { spec = substr(entry, 1, RSTART - 1); description = substr(entry, RSTART + RLENGTH) }
      split(spec, parts, " "); names = parts[1]; takes_value = (spec ~ / /) ? 1 : 0
      values = ""
      if (match(spec, /:one of [^=]*/)) {
        choices = substr(spec, RSTART + 8, RLENGTH - 8); sub(/ REQUIRED$/, "", choices)
        gsub(/,? or |, /, " ", choices); values = "choices:" choices
      }
      add_presets(description); next
    }
    /^      / && names != "" { add_presets($0); next }
    { flush() }
    END { flush() }
    function add_presets(text) {
      if (text ~ /array preset/) values = "presets:arrays"
      else if (text ~ /channel map preset/) values = "presets:channel-maps"
      else if (text ~ /processing config preset/) values = "presets:processing"
      else if (text ~ /limits preset/) values = "presets:limits"
    }'
}

# The words the positionals of `napkin $1` may be, where their type lists them (query's KIND:
# "TEXT:one of tests, hic, ..."), one a line; nothing when they are files or free text.
napkin_positional_choices() {
  napkin_help "$1" | awk '/^[A-Za-z].*:$/ { in_section = ($0 == "Positionals:"); next }
    in_section && /^  [A-Za-z]/ && match($0, /:one of [^=]*/) {
      choices = substr($0, RSTART + 8, RLENGTH - 8); sub(/ REQUIRED.*$/, "", choices)
      gsub(/,? or |, /, " ", choices); n = split(choices, words, " ")
      for (i = 1; i <= n; i++) print words[i]
    }'
}
