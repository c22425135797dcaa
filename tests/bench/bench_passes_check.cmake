# A reproduction's captured passes (BenchCase::capture, bench/bench_papers.cpp): the
# hybrid interactive frame's 4n layer passes and alpha clears, replayed on ours and on
# llvmpipe in the same run, must give a ratio; a skipped peer (Mesa refusing what the
# passes use) or a missing pair fails. The speed is not checked (a short --min-time).
#   cmake -DRETROGLASS=<exe> -P bench_passes_check.cmake
execute_process(
    COMMAND ${RETROGLASS} bench --threads 1 --filter "^hybrid_interactive_passes/" --min-time 0.01
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "bench of the captured passes exited with ${rc}:\n${out}\n${err}")
endif()
foreach(impl retroglass llvmpipe)
    if(NOT "${out}" MATCHES "hybrid_interactive_passes/${impl}/threads:1")
        message(FATAL_ERROR "no hybrid_interactive_passes/${impl} benchmark ran:\n${out}\n${err}")
    endif()
endforeach()
if("${out}${err}" MATCHES "error_occurred|Mesa lacks|ERROR OCCURRED")
    message(FATAL_ERROR "the llvmpipe side of the captured passes was skipped:\n${out}\n${err}")
endif()
if(NOT "${out}" MATCHES "hybrid_interactive_passes vs llvmpipe +[0-9]+\\.[0-9]+")
    message(FATAL_ERROR "no ratio of the captured passes to llvmpipe:\n${out}\n${err}")
endif()
