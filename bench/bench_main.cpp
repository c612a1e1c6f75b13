// Entry point of imm_bench: every BM_<Phase> family registers itself in its own file
// (bench_complex.cpp, bench_search.cpp, bench_mesh.cpp). Run with --benchmark_out=FILE
// --benchmark_out_format=json for the figures in BENCHMARKS.md.
#include <benchmark/benchmark.h>

BENCHMARK_MAIN();
