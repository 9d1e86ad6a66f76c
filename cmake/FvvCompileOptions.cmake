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
# libFuzzer's coverage instrumentation where the fuzz targets' inputs go: the
# parsers' libraries and files (fvv_fuzz_coverage), not the tracker and shape
# code around them, whose tests it would slow down several times over.
function(fvv_fuzz_coverage target)
  if(FVV_BUILD_FUZZERS)
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
endfunction()
function(fvv_fuzz_coverage_sources)
  if(FVV_BUILD_FUZZERS)
    set_source_files_properties(${ARGN} DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
                                PROPERTIES COMPILE_OPTIONS -fsanitize=fuzzer-no-link)
  endif()
endfunction()
