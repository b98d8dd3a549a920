# Warning flags for shadowkit's own targets (tests, samples, report). Dependencies are
# included as system headers so their warnings do not count.
set(SHADOWKIT_WARNING_FLAGS -Wall -Wextra -Wpedantic -Wconversion -Wshadow)
if(SHADOWKIT_WERROR)
  list(APPEND SHADOWKIT_WARNING_FLAGS -Werror)
endif()

function(shadowkit_warnings target)
  target_compile_options(${target} PRIVATE ${SHADOWKIT_WARNING_FLAGS})
endfunction()

# Looser set for code that wraps C APIs heavily (GL/EGL/Embree glue): -Wconversion stays,
# nothing is silenced globally; individual casts are explicit.
