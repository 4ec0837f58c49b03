# Strict warnings for every C target of the project (DEVELOPERS.md: src/ builds
# with -Wall -Wextra -Wconversion -Wshadow -Werror).  Use mc_strict_warnings(tgt).
set(MC_STRICT_WARNINGS
  -Wall -Wextra -Wconversion -Wsign-conversion -Wshadow -Wstrict-prototypes
  -Wmissing-prototypes -Wundef -Wdouble-promotion -Werror)

function(mc_strict_warnings target)
  target_compile_options(${target} PRIVATE ${MC_STRICT_WARNINGS})
endfunction()
