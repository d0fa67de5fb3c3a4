#!/usr/bin/env bash
# Writes napkin's bash completion from the built binary's --help (cmake/Packaging.cmake runs it at
# build time; the Debian package installs the result as share/bash-completion/completions/napkin).
# CLI11 has no completion generator; this one covers (packaging/README.md):
#   - the subcommands, as the first word that is not an option or an option's value;
#   - each subcommand's options, and the top-level options (--db, --quiet), which napkin also
#     accepts after the subcommand;
#   - the values of options whose type lists them (--format, --by, --units, ...: "one of ...");
#   - the values of options whose help names a preset (--array, --channel-map, --config): the
#     preset names installed beside napkin (<bindir>/../share/napkin/config/<kind>/*.json) and files;
#   - the words a positional may be where its type lists them (query's KIND);
#   - everything else (inputs, outputs, other option values): file names, one completion a file
#     (a name with spaces stays one word, also when the word typed is escaped or quoted);
#   - an option's value also in the --option=value form.
# Usage: bash_completion.sh <path to napkin> <output file>
set -euo pipefail
NAPKIN=$1
output=$2
# shellcheck source=packaging/cli_help.sh
. "$(dirname "$0")/cli_help.sh"

subcommands=$(napkin_subcommands | tr "\n" " " | sed "s/ $//")
[ -n "$subcommands" ] || { echo "bash_completion.sh: no subcommands in $NAPKIN --help" >&2; exit 1; }

# The options of one subcommand ("" = top level) as completion words.
options_words() { napkin_options "$1" | cut -f1 | tr ',' '\n'; }
# The case arms for the values of the options of subcommand $1 that take one, one arm per kind of
# value (choices, presets, else files); $2 is the pattern for the subcommand ("*" for the
# top-level options, which also follow any subcommand).
value_arms() {
  napkin_options "$1" | awk -F'\t' -v sub_pattern="$2" '$2 == 1 {
      n = split($1, names, ",")
      for (i = 1; i <= n; i++) arms[$3] = arms[$3] (arms[$3] == "" ? "" : "|") sub_pattern ":" names[i]
    }
    END {
      for (kind in arms) {
        if (kind ~ /^choices:/) action = "_napkin_words \"" substr(kind, 9) "\""
        else if (kind ~ /^presets:/) action = "_napkin_values " substr(kind, 9)
        else action = "_napkin_values \"\""
        printf "    %s) %s; return ;;\n", arms[kind], action
      }
    }' | sort
}

global_options=$(options_words "" | tr '\n' ' ' | sed 's/ $//')
{
  echo "# bash completion for napkin: generated from \`napkin --help\` of $("$NAPKIN" --version) by"
  echo "# packaging/bash_completion.sh (subcommands, their options, preset names, files)."
  echo "# shellcheck shell=bash"
  echo
  # The helpers do not depend on napkin's options: written as they are.
  cat << 'HELPERS'
# The word being completed as the shell will read it (quote removal): compgen matches file names
# literally, so "my\ d", "'my d" and "\"my d" must become "my d". bash quotes the completions
# again as file names (complete -o filenames).
_napkin_dequote() {
  local word=$1 out="" i
  case $word in
    \'*) printf '%s' "${word:1}"; return ;;
    \"*) word=${word:1} ;;
  esac
  for ((i = 0; i < ${#word}; i++)); do
    [[ ${word:i:1} == \\ ]] && ((++i))
    out+=${word:i:1}
  done
  printf '%s' "$out"
}

# Adds the file names that complete $cur, one completion a file: "my data.csv" stays one word.
_napkin_files() {
  local word
  word=$(_napkin_dequote "$cur")
  mapfile -t -O ${#COMPREPLY[@]} COMPREPLY < <(compgen -f -- "$word")
}

# Adds the words of $1 (a value's choices, query's KIND, the subcommands, options) that complete $cur.
_napkin_words() {
  mapfile -t -O ${#COMPREPLY[@]} COMPREPLY < <(compgen -W "$1" -- "$cur")
}

# Completes an option's value: the presets of config/$1 (arrays, processing, ...), and files.
_napkin_values() {
  local napkin_path config_dir
  napkin_path=$(type -P napkin) || napkin_path=""
  config_dir="${napkin_path%/*}/../share/napkin/config/$1"
  _napkin_files
  if [[ -n $1 && -d $config_dir ]]; then
    local presets=("$config_dir"/*.json)
    presets=("${presets[@]##*/}")
    _napkin_words "${presets[*]%.json}"
  fi
}

_napkin() {
  local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]} prefix=""
  # An option's value given as --option=value: bash splits the line at "=" (COMP_WORDBREAKS), so
  # "--format=" arrives as the words "--format" "=" (the word completed is empty) and "--format=c"
  # as "--format" "=" "c". Without "=" in COMP_WORDBREAKS it stays one word, which the
  # completions replace: they keep its "--format=".
  if [[ $cur == = && $prev == -* ]]; then
    cur=""
  elif [[ $prev == = ]] && ((COMP_CWORD >= 2)) && [[ ${COMP_WORDS[COMP_CWORD-2]} == -* ]]; then
    prev=${COMP_WORDS[COMP_CWORD-2]}
  elif [[ $cur == -*=* ]]; then
    prev=${cur%%=*}
    prefix=$prev=
    cur=${cur#*=}
  fi
  COMPREPLY=()
  _napkin_complete
  if [[ -n $prefix ]]; then
    COMPREPLY=("${COMPREPLY[@]/#/"$prefix"}")
  fi
}

HELPERS
  echo "# Completes \$cur after \$prev: the tables below are napkin's subcommands and options."
  echo "_napkin_complete() {"
  echo "  local sub=\"\" i"
  echo "  for ((i = 1; i < COMP_CWORD; i++)); do"
  echo "    case \${COMP_WORDS[i]} in"
  echo "      $(echo "$subcommands" | tr ' ' '|')) sub=\${COMP_WORDS[i]}; break ;;"
  echo "    esac"
  echo "  done"
  echo "  case \$sub:\$prev in"
  value_arms "" "*"
  for s in $subcommands; do value_arms "$s" "$s"; done
  echo "  esac"
  echo "  local options"
  echo "  case \$sub in"
  echo "    \"\") options=\"$global_options\" ;;"
  for s in $subcommands; do
    echo "    $s) options=\"$({ options_words "$s"; options_words ""; } | awk '!seen[$0]++' | tr '\n' ' ' | sed 's/ $//')\" ;;"
  done
  echo "  esac"
  echo "  if [[ \$cur == -* ]]; then"
  echo "    _napkin_words \"\$options\""
  echo "  elif [[ -z \$sub ]]; then"
  echo "    _napkin_words \"$subcommands\""
  echo "  else"
  echo "    case \$sub in"
  for s in $subcommands; do
    choices=$(napkin_positional_choices "$s" | tr '\n' ' ' | sed 's/ $//')
    [ -z "$choices" ] || echo "      $s) _napkin_words \"$choices\" ;;"
  done
  echo "      *) _napkin_files ;;"
  echo "    esac"
  echo "  fi"
  echo "}"
  echo "complete -o filenames -F _napkin napkin"
} > "$output.tmp"
mv "$output.tmp" "$output"
