// dc_learning sources land here (issue 4).
namespace dc { int learning_library_anchor = 0; }
