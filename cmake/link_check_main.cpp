/// \file
/// \brief The program of a module's link check (src/CMakeLists.txt): it calls nothing, but the
/// whole module is linked into it, so every symbol the module uses must come from the modules it
/// lists as dependencies.
int main() {
  return 0;
}
