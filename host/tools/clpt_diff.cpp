// clpt-diff: compares two images. (Being written; see issue 3.)
int main() { return 1; }
