// volguide command line: placeholder until the CLI lands (render | diff | info).
#include <cstdio>

int main(int argc, char** argv) {
    std::fprintf(stderr, "volguide: not implemented yet\n");
    return 2;
}
