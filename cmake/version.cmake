# Writes the build's version.cpp with the commit checked out now. Run by the funnel_version target
# at every build, so that outputs name the commit they were built from after a pull or a commit
# too, not the one of the first configure; configure_file rewrites the file (and so recompiles
# it) only when its text changes.
# Inputs: ROOT (source tree), SRC (version.cpp.in), DST (the generated file), PROJECT_VERSION.
execute_process(COMMAND git rev-parse --short=12 HEAD
  WORKING_DIRECTORY ${ROOT}
  OUTPUT_VARIABLE FUNNEL_GIT_COMMIT OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT FUNNEL_GIT_COMMIT)
  set(FUNNEL_GIT_COMMIT "unknown")
endif()
configure_file(${SRC} ${DST} @ONLY)
