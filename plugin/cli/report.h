/* Printing an import report, as aligned text for people or as one JSON object for programs. */
#ifndef WEFT_CLI_REPORT_H
#define WEFT_CLI_REPORT_H
#include <stdio.h>

#include "weft/weft.h"

void cli_report_text(FILE* out, const char* file, const weft_import_report* r);
/* Returns 0, or -1 when the JSON could not be built (out of memory); nothing is printed then. */
int cli_report_json(FILE* out, const char* file, const weft_import_report* r);

#endif
