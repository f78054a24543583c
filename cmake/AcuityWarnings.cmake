# Warnings for acuity's own targets only; third-party headers are included as SYSTEM.
function(acuity_target_warnings target)
  if(MSVC)
    target_compile_options(${target} PRIVATE /W4 $<$<BOOL:${ACUITY_WERROR}>:/WX>)
    return()
  endif()
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                         -Wno-sign-conversion $<$<BOOL:${ACUITY_WERROR}>:-Werror>)
  if(ACUITY_SANITIZE)
    # GCC 12 reports false maybe-uninitialized positives inside library templates under ASan.
    target_compile_options(${target} PRIVATE -Wno-error=maybe-uninitialized)
  endif()
endfunction()
