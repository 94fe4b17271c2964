// The sanitizers' default options for the sanitized subset's instrumented executables
// (cmake/mbgen_sanitizers.cmake): the runtime asks for these before it reads ASAN_OPTIONS,
// UBSAN_OPTIONS and LSAN_OPTIONS, which still override them flag by flag.
extern "C" {
// Abort on the first report (a test that reports fails), and look for use after return too.
const char* __asan_default_options() {
  return "abort_on_error=1:detect_stack_use_after_return=1:strict_string_checks=1";
}
// -fno-sanitize-recover=all already ends the run at a report; the stack says where.
const char* __ubsan_default_options() { return "print_stacktrace=1:halt_on_error=1"; }
// urdfdom's graph, leaked once when it fails a parse mbgen did not refuse first.
const char* __lsan_default_options() { return "suppressions=" MBGEN_LSAN_SUPPRESSIONS; }
}
