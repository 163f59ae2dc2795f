# Reads a ctest log written with --output-on-failure and prints "tracer" when every failed test's
# output holds LeakSanitizer's own fatal error (its tracer thread crashed while the process
# exited, no leak reported: google/sanitizers#1353, seen with llvmpipe's threads ending), else
# "other" (any real failure, leak report, timeout, or no failure at all).
/ Test +#[0-9]+: .*\*\*\*/ { name = $4; fails[name] = 1; cur = name; next }
/ Test +#[0-9]+: / || /^ +Start +[0-9]+: / { cur = ""; next }
cur != "" && /LeakSanitizer has encountered a fatal error/ { tracer[cur] = 1 }
END {
  n = 0; bad = 0
  for (t in fails) { n++; if (!(t in tracer)) bad++ }
  print (n > 0 && bad == 0) ? "tracer" : "other"
}
