# The Debian package (`make package`, README "Install without building"): CPack's DEB generator
# over everything `cmake --install` installs (every install component in one package), plus what
# only a package needs, generated from the built binary at build time (packaging/README.md):
# the man page napkin(1) from the CLI's --help (Debian help2man) and a bash completion.
# Off by default: the test and bench builds neither run help2man nor install these.
option(NAPKIN_BUILD_PACKAGE "Generate the man page and bash completion and configure the Debian package (make package)" OFF)
if(NOT NAPKIN_BUILD_PACKAGE)
  return()
endif()

find_program(NAPKIN_HELP2MAN help2man REQUIRED)  # Debian help2man
find_program(NAPKIN_GZIP gzip REQUIRED)
find_program(NAPKIN_BASH bash REQUIRED)
# CPack runs dpkg-shlibdeps (Debian dpkg-dev) and file to compute Depends; found here, at configure time.
find_program(NAPKIN_DPKG_SHLIBDEPS dpkg-shlibdeps REQUIRED)
find_program(NAPKIN_FILE file REQUIRED)

set(_packaging_dir ${PROJECT_BINARY_DIR}/packaging)
set(_man_page ${_packaging_dir}/napkin.1)
set(_man_sections ${_packaging_dir}/napkin.h2m)
set(_completion ${_packaging_dir}/napkin.bash-completion)

# The man page: help2man reads `napkin --help` and `napkin --version`; each subcommand's
# --help is added as a COMMANDS section (packaging/man_sections.sh). Gzipped with -9, as Debian
# policy 12.1 asks of manual pages, and -n (no file name or time stamp in gzip's header).
add_custom_command(
  OUTPUT ${_man_page}.gz
  COMMAND ${NAPKIN_BASH} ${PROJECT_SOURCE_DIR}/packaging/man_sections.sh $<TARGET_FILE:napkin> ${_man_sections}
  COMMAND ${NAPKIN_HELP2MAN} --no-info --section=1 --no-discard-stderr
          "--name=head kinematics and injury criteria for catalogues of crash tests"
          --include=${_man_sections} --output=${_man_page} $<TARGET_FILE:napkin>
  COMMAND ${NAPKIN_GZIP} -n -9 -f ${_man_page}
  DEPENDS napkin ${PROJECT_SOURCE_DIR}/packaging/man_sections.sh ${PROJECT_SOURCE_DIR}/packaging/cli_help.sh
  WORKING_DIRECTORY ${_packaging_dir}
  COMMENT "help2man: napkin(1) from napkin --help"
  VERBATIM)
add_custom_command(
  OUTPUT ${_completion}
  COMMAND ${NAPKIN_BASH} ${PROJECT_SOURCE_DIR}/packaging/bash_completion.sh $<TARGET_FILE:napkin> ${_completion}
  DEPENDS napkin ${PROJECT_SOURCE_DIR}/packaging/bash_completion.sh ${PROJECT_SOURCE_DIR}/packaging/cli_help.sh
  WORKING_DIRECTORY ${_packaging_dir}
  COMMENT "bash completion of napkin's subcommands and options from napkin --help"
  VERBATIM)
# The package's changelog (Debian policy 12.7), packaging/changelog in Debian's format: napkin is
# a native package (its version has no Debian revision), so lintian wants it as
# /usr/share/doc/napkin/changelog.gz, not changelog.Debian.gz. Its latest entry must be this
# version: dpkg and lintian read the package's version from it.
file(STRINGS ${PROJECT_SOURCE_DIR}/packaging/changelog _changelog_head LIMIT_COUNT 1)
string(REGEX REPLACE "^napkin \\(([^)]*)\\) .*" "\\1" _changelog_version "${_changelog_head}")
if(NOT _changelog_version STREQUAL PROJECT_VERSION)
  message(FATAL_ERROR "packaging/changelog: its latest entry is \"${_changelog_head}\", not napkin (${PROJECT_VERSION}); add an entry for the version in project().")
endif()
set(_changelog ${_packaging_dir}/changelog)
add_custom_command(
  OUTPUT ${_changelog}.gz
  COMMAND ${CMAKE_COMMAND} -E copy ${PROJECT_SOURCE_DIR}/packaging/changelog ${_changelog}
  COMMAND ${NAPKIN_GZIP} -n -9 -f ${_changelog}
  DEPENDS ${PROJECT_SOURCE_DIR}/packaging/changelog
  WORKING_DIRECTORY ${_packaging_dir}
  COMMENT "gzip: the package's changelog.gz"
  VERBATIM)
file(MAKE_DIRECTORY ${_packaging_dir})
add_custom_target(napkin_package_docs ALL DEPENDS ${_man_page}.gz ${_completion} ${_changelog}.gz)
install(FILES ${_man_page}.gz DESTINATION share/man/man1)
install(FILES ${_completion} DESTINATION share/bash-completion/completions RENAME napkin)
# `napkin serve` as a system service (docs/serve.md "Running it as a service"): the systemd unit,
# installed disabled, and its settings, a conffile (packaging/conffiles) that an upgrade keeps.
install(FILES ${PROJECT_SOURCE_DIR}/packaging/napkin-serve.service DESTINATION /lib/systemd/system)
install(FILES ${PROJECT_SOURCE_DIR}/packaging/napkin.default DESTINATION /etc/default RENAME napkin)
# Debian policy 12.5: the copyright file, uncompressed, in machine-readable DEP-5 format.
install(FILES ${PROJECT_SOURCE_DIR}/packaging/copyright ${_changelog}.gz DESTINATION share/doc/napkin)

# The package: napkin_<version>_<arch>.deb (Debian's file naming), version from project().
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME napkin)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_STRIP_FILES ON)  # Debian policy 10.1: binaries are stripped
# The maintainer script: prerm removes the bytecode python3 wrote beside the module, which dpkg
# does not know (packaging/prerm); mode 0755 as lintian wants.
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${PROJECT_SOURCE_DIR}/packaging/prerm ${PROJECT_SOURCE_DIR}/packaging/conffiles)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(NAPKIN_PACKAGE_MAINTAINER "napkin maintainers <maintainers@users.noreply.h-seed-27ac8218.example>"
    CACHE STRING "The Debian package's Maintainer field")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${NAPKIN_PACKAGE_MAINTAINER}")
set(CPACK_PACKAGE_CONTACT "${NAPKIN_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "head kinematics and injury criteria for catalogues of crash tests")
# The extended description; CPack puts the summary above it.
set(CPACK_DEBIAN_PACKAGE_DESCRIPTION
    "napkin computes six-degree-of-freedom head kinematics from crash-test head
instrumentation (nine-accelerometer and angular-rate arrays, ISO-MME, UDS-1992,
CSV) and the injury criteria (HIC, BrIC, ...) with their risk curves, and keeps
tests and results in a SQLite catalogue that it queries, compares and reports.

The package holds the napkin command with its array and processing presets,
the Python module napkin (numpy in and out), the manual page, a bash
completion and the systemd unit napkin-serve.service (napkin serve: an HTTP
API over the catalogue and an inbox processed as tests arrive).")
# Depends: the shared libraries' packages, computed by dpkg-shlibdeps over the installed ELF
# files (napkin and the Python extension), never typed by hand. CPack appends them to
# CPACK_DEBIAN_PACKAGE_DEPENDS, which holds what dpkg-shlibdeps cannot see: the Python
# extension is loaded by python3 (it does not link libpython) and imports numpy at run time.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
if(TARGET napkin_python)
  # The extension's file name carries its interpreter's ABI (pybind11 sets the target's SUFFIX to
  # ".cpython-3XY-<triplet>.so"): python3 of that minor version only.
  get_target_property(_python_suffix napkin_python SUFFIX)
  if(NOT _python_suffix MATCHES "^\\.cpython-([0-9])([0-9]+)-")
    message(FATAL_ERROR "Packaging.cmake: cannot read the Python version from the extension's suffix ${_python_suffix}")
  endif()
  set(_python_version ${CMAKE_MATCH_1}.${CMAKE_MATCH_2})
  math(EXPR _python_next_minor "${CMAKE_MATCH_2} + 1")
  set(CPACK_DEBIAN_PACKAGE_DEPENDS
      "python3 (>= ${_python_version}), python3 (<< ${CMAKE_MATCH_1}.${_python_next_minor}), python3-numpy")
  # Catalogue.query_frame returns a pandas DataFrame; without pandas it raises an ImportError
  # naming python3-pandas (docs/python.md), so pandas is suggested, not depended on.
  set(CPACK_DEBIAN_PACKAGE_SUGGESTS python3-pandas)
endif()
include(CPack)
