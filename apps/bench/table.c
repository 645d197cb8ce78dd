/* Text buffers, the CSV table and timing statistics. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"

void bench_text_add(bench_text* t, const char* format, ...)
{
    if (t->failed)
        return;
    va_list args;
    va_start(args, format);
    int n = vsnprintf(NULL, 0, format, args);
    va_end(args);
    if (n < 0) {
        t->failed = true;
        return;
    }
    size_t need = t->length + (size_t)n + 1;
    if (need > t->capacity) {
        size_t capacity = t->capacity ? 2 * t->capacity : 256;
        while (capacity < need)
            capacity *= 2;
        char* grown = realloc(t->data, capacity);
        if (!grown) {
            t->failed = true;
            return;
        }
        t->data = grown;
        t->capacity = capacity;
    }
    va_start(args, format);
    vsnprintf(t->data + t->length, t->capacity - t->length, format, args);
    va_end(args);
    t->length += (size_t)n;
}

void bench_text_free(bench_text* t)
{
    free(t->data);
    *t = (bench_text){0};
}

void bench_table_init(bench_table* t, const char* const* columns, uint32_t count)
{
    *t = (bench_table){.columns = columns, .column_count = count};
}

void bench_table_free(bench_table* t)
{
    for (size_t i = 0; i < (size_t)t->rows * t->column_count; i++)
        free(t->cells[i]);
    free(t->cells);
    t->cells = NULL;
    t->rows = t->capacity = 0;
}

void bench_table_row(bench_table* t)
{
    if (t->failed)
        return;
    if (t->rows == t->capacity) {
        uint32_t capacity = t->capacity ? 2 * t->capacity : 64;
        char** grown = realloc(t->cells, (size_t)capacity * t->column_count * sizeof *grown);
        if (!grown) {
            t->failed = true;
            return;
        }
        t->cells = grown;
        t->capacity = capacity;
    }
    memset(&t->cells[(size_t)t->rows * t->column_count], 0, t->column_count * sizeof *t->cells);
    t->rows++;
}

static int column_of(const bench_table* t, const char* column)
{
    for (uint32_t c = 0; c < t->column_count; c++)
        if (!strcmp(t->columns[c], column))
            return (int)c;
    return -1;
}

static void set_cell(bench_table* t, uint32_t row, const char* column, const char* value)
{
    int c = column_of(t, column);
    if (t->failed || row >= t->rows || c < 0) {
        t->failed = true;
        return;
    }
    char** cell = &t->cells[(size_t)row * t->column_count + (size_t)c];
    free(*cell);
    *cell = strdup(value);
    if (!*cell)
        t->failed = true;
}

void bench_table_str(bench_table* t, const char* column, const char* value)
{
    set_cell(t, t->rows ? t->rows - 1 : 0, column, value);
}

void bench_table_set_int(bench_table* t, uint32_t row, const char* column, uint64_t value)
{
    char text[32];
    snprintf(text, sizeof text, "%llu", (unsigned long long)value);
    set_cell(t, row, column, text);
}

void bench_table_num(bench_table* t, const char* column, double value)
{
    char text[32];
    if (isnan(value))
        snprintf(text, sizeof text, "nan");
    else if (isinf(value))
        snprintf(text, sizeof text, value > 0 ? "inf" : "-inf");
    else
        snprintf(text, sizeof text, "%.6g", value);
    bench_table_str(t, column, text);
}

void bench_table_int(bench_table* t, const char* column, uint64_t value)
{
    char text[32];
    snprintf(text, sizeof text, "%llu", (unsigned long long)value);
    bench_table_str(t, column, text);
}

const char* bench_table_get_str(const bench_table* t, uint32_t row, const char* column)
{
    int c = column_of(t, column);
    if (c < 0 || row >= t->rows)
        return NULL;
    return t->cells[(size_t)row * t->column_count + (size_t)c];
}

double bench_table_get(const bench_table* t, uint32_t row, const char* column)
{
    const char* text = bench_table_get_str(t, row, column);
    if (!text)
        return NAN;
    char* end;
    double v = strtod(text, &end);
    return *end ? NAN : v;
}

/* RFC 4180: quoted when it holds a comma, a quote or a line break. */
static bool write_cell(FILE* file, const char* value)
{
    if (!value)
        return true;
    if (!strpbrk(value, ",\"\n\r"))
        return fputs(value, file) >= 0;
    if (fputc('"', file) == EOF)
        return false;
    for (const char* c = value; *c; c++)
        if ((*c == '"' && fputc('"', file) == EOF) || fputc(*c, file) == EOF)
            return false;
    return fputc('"', file) != EOF;
}

bool bench_table_write(FILE* file, void* user)
{
    const bench_table* t = user;
    for (uint32_t c = 0; c < t->column_count; c++)
        if (fprintf(file, "%s,", t->columns[c]) < 0)
            return false;
    if (fputs("device\n", file) < 0)
        return false;
    for (uint32_t r = 0; r < t->rows; r++) {
        for (uint32_t c = 0; c < t->column_count; c++)
            if (!write_cell(file, t->cells[(size_t)r * t->column_count + c]) || fputc(',', file) == EOF)
                return false;
        if (!write_cell(file, t->device ? t->device : "") || fputc('\n', file) == EOF)
            return false;
    }
    return true;
}

int bench_compare_doubles(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

bench_timing bench_timing_of(double* samples, uint32_t n)
{
    if (n == 0)
        return (bench_timing){NAN, NAN, NAN};
    qsort(samples, n, sizeof *samples, bench_compare_doubles);
    double median = n % 2 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
    return (bench_timing){median, samples[0], samples[n - 1]};
}
