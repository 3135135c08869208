#include <iostream>
int main() { std::cout << "woven " << WOVEN_VERSION << "\n"; }
