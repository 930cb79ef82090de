// Film's copies, moves and destruction, compiled once (film.h).
#include "kernels/render/film.h"

namespace pt {

Film::Film(const Film&) = default;
Film::Film(Film&&) noexcept = default;
Film& Film::operator=(const Film&) = default;
Film& Film::operator=(Film&&) noexcept = default;
Film::~Film() = default;

}  // namespace pt
