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
#   - everything else (inputs, outputs, other option values): file names.
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
        if (kind ~ /^choices:/) action = "COMPREPLY=($(compgen -W \"" substr(kind, 9) "\" -- \"$cur\"))"
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
  echo
  echo "# Completes an option's value: the presets of config/\$1 (arrays, processing, ...), and files."
  echo "_napkin_values() {"
  echo "  local napkin_path config_dir"
  echo "  napkin_path=\$(type -P napkin) || napkin_path=\"\""
  echo "  config_dir=\"\${napkin_path%/*}/../share/napkin/config/\$1\""
  echo "  COMPREPLY=(\$(compgen -f -- \"\$cur\"))"
  echo "  if [[ -n \$1 && -d \$config_dir ]]; then"
  echo "    local presets=(\"\$config_dir\"/*.json)"
  echo "    presets=(\"\${presets[@]##*/}\")"
  echo "    COMPREPLY+=(\$(compgen -W \"\${presets[*]%.json}\" -- \"\$cur\"))"
  echo "  fi"
  echo "}"
  echo
  echo "_napkin() {"
  echo "  local cur=\${COMP_WORDS[COMP_CWORD]} prev=\${COMP_WORDS[COMP_CWORD-1]} sub=\"\" i"
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
  echo "    COMPREPLY=(\$(compgen -W \"\$options\" -- \"\$cur\"))"
  echo "  elif [[ -z \$sub ]]; then"
  echo "    COMPREPLY=(\$(compgen -W \"$subcommands\" -- \"\$cur\"))"
  echo "  else"
  echo "    case \$sub in"
  for s in $subcommands; do
    choices=$(napkin_positional_choices "$s" | tr '\n' ' ' | sed 's/ $//')
    [ -z "$choices" ] || echo "      $s) COMPREPLY=(\$(compgen -W \"$choices\" -- \"\$cur\")) ;;"
  done
  echo "      *) COMPREPLY=(\$(compgen -f -- \"\$cur\")) ;;"
  echo "    esac"
  echo "  fi"
  echo "}"
  echo "complete -o filenames -F _napkin napkin"
} > "$output.tmp"
mv "$output.tmp" "$output"
