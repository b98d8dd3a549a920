# docs.rules: fails with the list of documentation blocks that break the rules of
# tests/CONVENTIONS.md ("Documentation blocks"). Input: ERRORS (a file, one rule broken per line), SUMMARY.
file(READ ${ERRORS} text)
string(STRIP "${text}" text)
if(text)
  message(FATAL_ERROR "documentation blocks that are not compiled:\n${text}")
endif()
message(STATUS "docs: ${SUMMARY}; every block is compiled")
