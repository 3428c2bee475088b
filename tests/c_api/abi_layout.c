/* par2d.h's ABI against the layout recorded for it (tests/c_api/abi_layout.txt): within one ABI
 * (PAR2D_ABI_MAJOR.PAR2D_ABI_MINOR, the SONAME) no struct may change its size or a field its
 * offset or size, and no enumerator its value (new enumerators may be added). The table of
 * structs, fields and enumerators is generated from the header (abi_table.py), so nothing in it
 * can be forgotten. Usage: par2d_abi_layout RECORDED_FILE, or --print to write the record. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "par2d/par2d.h"
#include "par2d_abi_table.h"

typedef struct entry {
  const char* kind; /* "struct", "field" or "enum" */
  const char* name;
  long long a, b;   /* size; offset and size; value */
} entry;

#define STRUCT(s) {"struct", #s, (long long)sizeof(s), -1},
#define FIELD(s, f) {"field", #s "." #f, (long long)offsetof(s, f), (long long)sizeof(((s*)0)->f)},
#define ENUM(e) {"enum", #e, (long long)(e), -1},
static const entry table[] = {PAR2D_ABI_TABLE};
static const size_t table_size = sizeof table / sizeof table[0];

static void print_entry(FILE* f, const entry* e) {
  if (e->b < 0) fprintf(f, "%s %s %lld\n", e->kind, e->name, e->a);
  else fprintf(f, "%s %s %lld %lld\n", e->kind, e->name, e->a, e->b);
}

static const entry* find(const entry* entries, size_t n, const char* kind, const char* name) {
  for (size_t i = 0; i < n; ++i)
    if (strcmp(entries[i].kind, kind) == 0 && strcmp(entries[i].name, name) == 0) return &entries[i];
  return NULL;
}

int main(int argc, char** argv) {
  if (argc == 2 && strcmp(argv[1], "--print") == 0) {
    printf("abi %d.%d\n", PAR2D_ABI_MAJOR, PAR2D_ABI_MINOR);
    for (size_t i = 0; i < table_size; ++i) print_entry(stdout, &table[i]);
    return 0;
  }
  if (argc != 2) {
    fprintf(stderr, "usage: par2d_abi_layout RECORDED_FILE | --print\n");
    return 2;
  }
  FILE* f = fopen(argv[1], "r");
  if (f == NULL) {
    fprintf(stderr, "%s: cannot open\n", argv[1]);
    return 1;
  }
  static entry recorded[4096];
  static char names[4096][128];
  static char kinds[4096][8];
  size_t n = 0;
  int major = -1, minor = -1, failures = 0;
  char line[256];
  if (fgets(line, sizeof line, f) == NULL || sscanf(line, "abi %d.%d", &major, &minor) != 2) {
    fprintf(stderr, "%s:1: expected 'abi MAJOR.MINOR'\n", argv[1]);
    fclose(f);
    return 1;
  }
  for (int at = 2; fgets(line, sizeof line, f) != NULL && n < 4096; ++at) {
    long long a = 0, b = -1;
    const int got = sscanf(line, "%7s %127s %lld %lld", kinds[n], names[n], &a, &b);
    if (got < 3) {
      fprintf(stderr, "%s:%d: expected 'KIND NAME VALUE...'\n", argv[1], at);
      ++failures;
      continue;
    }
    recorded[n] = (entry){kinds[n], names[n], a, got == 4 ? b : -1};
    ++n;
  }
  fclose(f);
  if (major != PAR2D_ABI_MAJOR || minor != PAR2D_ABI_MINOR) {
    fprintf(stderr, "%s records ABI %d.%d, par2d.h declares %d.%d: record the new ABI's layout\n", argv[1], major,
            minor, PAR2D_ABI_MAJOR, PAR2D_ABI_MINOR);
    ++failures;
  }
  /* Structs and fields: exactly as recorded, none added or removed. */
  for (size_t i = 0; i < table_size; ++i) {
    const entry* e = &table[i];
    if (strcmp(e->kind, "enum") == 0) continue;
    const entry* r = find(recorded, n, e->kind, e->name);
    if (r == NULL || r->a != e->a || r->b != e->b) {
      fprintf(stderr, "par2d.h now has: ");
      print_entry(stderr, e);
      if (r != NULL) {
        fprintf(stderr, "         recorded: ");
        print_entry(stderr, r);
      }
      ++failures;
    }
  }
  for (size_t i = 0; i < n; ++i) {
    const entry* r = &recorded[i];
    const entry* e = find(table, table_size, r->kind, r->name);
    if (e == NULL) {
      fprintf(stderr, "par2d.h no longer has: ");
      print_entry(stderr, r);
      ++failures;
    } else if (strcmp(r->kind, "enum") == 0 && e->a != r->a) {
      fprintf(stderr, "enumerator %s is now %lld, recorded %lld\n", r->name, e->a, r->a);
      ++failures;
    }
  }
  if (failures > 0) {
    fprintf(stderr,
            "par2d.h's ABI %d.%d differs from %s. A released ABI never changes: if %d.%d was released,\n"
            "bump the version's minor (CMakeLists.txt, include/par2d/version.hpp, PAR2D_ABI_MINOR; the\n"
            "SONAME follows). Then record the layout: par2d_abi_layout --print > tests/c_api/abi_layout.txt\n",
            PAR2D_ABI_MAJOR, PAR2D_ABI_MINOR, argv[1], PAR2D_ABI_MAJOR, PAR2D_ABI_MINOR);
    return 1;
  }
  printf("ABI %d.%d: %zu structs, fields and enumerators as recorded\n", PAR2D_ABI_MAJOR, PAR2D_ABI_MINOR, table_size);
  return 0;
}
