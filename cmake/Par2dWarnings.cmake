# Warning flags shared by every par2d target.
# -Wno-missing-field-initializers: the scene structs are aggregates whose optional members
# (range, cone, mask, ...) have defaults; `Light{shape, color, intensity}` is the intended use.
function(par2d_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
    -Wno-sign-conversion -Wno-missing-field-initializers)
endfunction()
