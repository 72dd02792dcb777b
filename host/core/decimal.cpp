#include "core/decimal.h"

namespace pmcr {

namespace {

bool isDigit(char c) { return c >= '0' && c <= '9'; }

// Skips the digits at text[i...]; returns how many there were.
size_t skipDigits(std::string_view text, size_t& i) {
    const size_t start = i;
    while (i < text.size() && isDigit(text[i])) ++i;
    return i - start;
}

void skipSign(std::string_view text, size_t& i) {
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
}

}  // namespace

bool isDecimalInteger(std::string_view text) {
    size_t i = 0;
    skipSign(text, i);
    return skipDigits(text, i) > 0 && i == text.size();
}

bool isDecimalNumber(std::string_view text) {
    size_t i = 0;
    skipSign(text, i);
    size_t digits = skipDigits(text, i);
    if (i < text.size() && text[i] == '.') {
        ++i;
        digits += skipDigits(text, i);
    }
    if (digits == 0) return false;
    if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        ++i;
        skipSign(text, i);
        if (skipDigits(text, i) == 0) return false;
    }
    return i == text.size();
}

}  // namespace pmcr
