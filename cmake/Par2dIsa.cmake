# Per-ISA kernel files: each `*_<isa>.cpp` gets its own target flags, and optimisation
# even in Debug (at -O0 shared inline helpers are emitted in the AVX object too, and
# the linker may hand that copy to SSE callers).
set(PAR2D_ISA_FLAGS_sse4_2 -msse4.2 -mpopcnt)
set(PAR2D_ISA_FLAGS_avx2 -mavx2 -mfma -mbmi -mbmi2 -mlzcnt -mpopcnt -Wno-uninitialized -Wno-maybe-uninitialized)
set(PAR2D_ISA_FLAGS_avx512 -mavx512f -mavx512bw -mavx512dq -mavx512vl -mavx512cd -mavx2 -mfma -mbmi -mbmi2 -mlzcnt -mpopcnt -Wno-uninitialized -Wno-maybe-uninitialized)

function(par2d_isa_source file isa)
  set(flags ${PAR2D_ISA_FLAGS_${isa}})
  if(NOT flags)
    message(FATAL_ERROR "unknown ISA ${isa} for ${file}")
  endif()
  set_source_files_properties(${file} PROPERTIES COMPILE_OPTIONS "${flags};-O3")
endfunction()
