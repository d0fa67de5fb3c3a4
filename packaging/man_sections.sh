#!/usr/bin/env bash
# Writes the help2man include file of napkin(1) (cmake/Packaging.cmake runs it at build time):
# help2man turns `napkin --help` into NAME, SYNOPSIS, DESCRIPTION and OPTIONS with the
# subcommands' one-line summaries; this adds a COMMANDS section with each subcommand's own
# --help (its options), verbatim, and FILES (where the presets are) and SEE ALSO.
# Usage: man_sections.sh <path to napkin> <output file>
set -euo pipefail
NAPKIN=$1
output=$2
# shellcheck source=packaging/cli_help.sh
. "$(dirname "$0")/cli_help.sh"

subcommands=$(napkin_subcommands)
[ -n "$subcommands" ] || { echo "man_sections.sh: no subcommands in $NAPKIN --help" >&2; exit 1; }

# roff text, verbatim: backslashes escaped (\e), and lines that start with a control character
# (. or ') protected with the zero-width \&.
roff_verbatim() { sed -e 's/\\/\\e/g' -e "s/^\([.']\)/\\\\\&\1/"; }

{
  cat <<'ROFF'
[COMMANDS]
Each subcommand's options, as \fBnapkin\fR \fIsubcommand\fR \fB\-\-help\fR prints them.
The options above (\fB\-\-db\fR, \fB\-\-quiet\fR) may also follow the subcommand.
ROFF
  for s in $subcommands; do
    echo ".SS \"napkin $s\""
    echo ".nf"
    napkin_help "$s" | roff_verbatim
    echo ".fi"
  done
  cat <<'ROFF'

[FILES]
.TP
.I /usr/share/napkin/config/
the presets: sensor arrays (\fIarrays/\fR), processing configs (\fIprocessing/\fR) and
channel maps (\fIchannel\-maps/\fR), named by \fB\-\-array\fR, \fB\-\-config\fR and
\fB\-\-channel\-map\fR. \fBNAPKIN_CONFIG_DIR\fR names another folder.

[SEE ALSO]
The Python module: \fBpython3 \-c 'import napkin; help(napkin)'\fR.
ROFF
} > "$output.tmp"
mv "$output.tmp" "$output"
