// A return statement at the top level of the file, with an object whose getter throws
// a text the host once took for its own ("out of memory").
return { get predict() { throw new Error('out of memory'); } };
