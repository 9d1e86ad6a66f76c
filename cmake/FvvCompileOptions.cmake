# Warning and sanitizer flags shared by every fvv target (fvv_set_options(target)).
function(fvv_set_options target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow -Wno-unused-parameter)
  if(FVV_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  # The decoder's bit-exactness must not depend on floating-point contraction; the
  # decode path is integer-only, and this keeps encoder-side estimates reproducible too.
  target_compile_options(${target} PRIVATE -ffp-contract=off)
endfunction()

if(FVV_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
if(FVV_TSAN)
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
endif()
if(FVV_BUILD_FUZZERS)
  # Coverage instrumentation for every library the fuzz targets link.
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
