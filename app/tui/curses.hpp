#pragma once
// ncursesw with the wide-character API (braille cells are one wchar_t each).
#ifndef NCURSES_WIDECHAR
#define NCURSES_WIDECHAR 1
#endif
#include <ncurses.h>
