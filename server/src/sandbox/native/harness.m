% The harness of a student's MATLAB file, in GNU Octave inside the operating-system
% sandbox (see `server/src/sandbox/native`): the counterpart of `harness.py`, with the
% same requests and answers, one JSON object a line each way:
%
%   first line      {"source": ..., "file": "ekf_localization.m", "functions": [...]}
%                   answered {"ready": true}
%   {"load": true}  the file evaluated afresh: {"defined": [names]} or {"error": text}
%   {"call": name, "args": [{"value": ...}, ...]}
%                   {"output": value} or {"error": text}
%
% The JavaScript harness outside the sandbox grades; this one only carries values
% across, converting between the contract's shapes and the lab's MATLAB conventions as
% `functions` (`Exercise::interface`) describes each function: vectors as columns,
% 1-based indices, per-landmark outputs along the last dimension, flags as 0 and 1 too,
% headings wrapped (the lab leaves them unwrapped; the contract compares them modulo
% 2 pi), the lab's trailing arguments, and its editions that read the map and the noise
% from global variables. The file is sourced as a script, so that a student's lab files
% pasted one after another (each function closed by `end`) define every function; files
% whose functions have no `end` are split into one function file each. Everything the
% student's code prints is captured and dropped. Nothing here is trusted by the grader.
function estlab_harness ()
  page_screen_output (false);
  more off;
  warning ('off', 'all');
  % Each request comes with an empty line after it: fgetl looks a character past the
  % end of the line it reads, and has the empty one to look at.
  setup = jsondecode (fgetl (stdin));
  specs = struct ();
  for k = 1:numel (setup.functions)
    spec = listed (setup.functions, k);
    spec.arguments = listed (spec.arguments);
    spec.outputs = listed (spec.outputs);
    spec.declared = [];
    specs.(spec.name) = spec;
  end
  reply ('{"ready":true}');
  while (true)
    line = fgetl (stdin);
    if (! ischar (line))
      return;
    elseif (isempty (line))
      continue;
    end
    request = jsondecode (line);
    if (isfield (request, 'load'))
      reply (load_file (setup.source, setup.file));
    else
      [text, specs] = call (request.call, request.args, specs, setup.file);
      reply (text);
    end
  end
end

% The `k`th of a list jsondecode made (a struct array, or a cell array where the items'
% fields differ), or all of it as a struct array.
function item = listed (list, k)
  if (iscell (list))
    list = [list{:}];
  end
  item = list;
  if (nargin > 1)
    item = list(k);
  end
end

function reply (text)
  fputs (stdout, [text "\n"]);
  fflush (stdout);
end

% Where the student's file is written: as a script, or one file a function.
function folder = student_folder ()
  folder = '/tmp/estlab-student';
end

function text = load_file (code, file)
  persistent names split;
  folder = student_folder ();
  for k = 1:numel (names)
    clear (names{k});
  end
  clear -global;
  if (isempty (split))
    names = declared (code);
    [split, text] = write_file (code, file, names, folder);
    if (! isempty (text))
      return;
    end
  end
  try
    if (! split)
      evalc ('source ([folder "/estlab_student.m"]);');
    end
  catch err
    text = error_text (err, file);
    return;
  end
  defined = {};
  for k = 1:numel (names)
    if (any (exist (names{k}) == [2 103]))
      defined{end + 1} = names{k};
    end
  end
  answer.defined = defined;
  text = jsonencode (answer);
end

% The names of the functions `source` declares.
function names = declared (code)
  found = regexp (code, ['^[ \t]*function[ \t]+(?:\[[^\]]*\][ \t]*=[ \t]*|' ...
                           '\w+[ \t]*=[ \t]*)?(\w+)'], 'tokens', 'lineanchors');
  names = unique (cellfun (@(t) t{1}, found, 'UniformOutput', false));
end

% Writes the file as a script (`1;` first, which shifts its lines by one), or, when its
% functions have no `end` and so cannot share a script, each function in a file of its
% own, as far down as it was in the student's file.
function [split, text] = write_file (code, file, names, folder)
  text = '';
  mkdir (folder);
  script = [folder "/estlab_student.m"];
  put (script, ["1;\n" code]);
  addpath (folder);
  try
    evalc ('source (script);');
    split = false;
    return;
  catch err
    if (isempty (strfind (err.message, 'nested functions')))
      split = false;
      return;
    end
  end
  delete (script);
  split = true;
  lines = strsplit (code, "\n", "CollapseDelimiters", false);
  starts = find (! cellfun (@isempty, regexp (lines, '^[ \t]*function\>', 'once')));
  starts(end + 1) = numel (lines) + 1;
  for k = 1:numel (starts) - 1
    chunk = lines(starts(k):starts(k + 1) - 1);
    name = declared (chunk{1});
    if (isempty (name))
      continue;
    end
    padding = repmat ("\n", 1, starts(k) - 1);
    put ([folder "/" name{1} ".m"], [padding strjoin(chunk, "\n") "\n"]);
  end
  rehash ();
end

function put (path, text)
  fid = fopen (path, 'w');
  fputs (fid, text);
  fclose (fid);
end

function [text, specs] = call (name, args, specs, file)
  values = cell (1, numel (args));
  for k = 1:numel (args)
    values{k} = argument (args(k).value);
  end
  spec = [];
  if (isfield (specs, name))
    spec = specs.(name);
    if (isempty (spec.declared))
      specs.(name).declared = nargin (name);
      spec = specs.(name);
    end
  end
  try
    [args, outputs] = arguments_for (name, values, spec);
    out = cell (1, outputs);
    evalc ('[out{1:outputs}] = feval (name, args{:});');
    text = ['{"output":' output_text(out, spec) '}'];
  catch err
    text = error_text (err, file);
  end
end

% The arguments as the student's function takes them, and how many values it returns.
function [args, outputs] = arguments_for (name, args, spec)
  outputs = 1;
  if (isempty (spec))
    return;
  end
  outputs = numel (spec.outputs);
  given = spec.arguments;
  for k = 1:numel (given)
    if (given(k).index)
      args{k} = args{k} + 1;
    end
  end
  declared = spec.declared;
  if (declared >= 0 && declared < numel (args))
    % An edition of the lab that reads these from globals; then as many as declared.
    keep = true (1, numel (args));
    for k = 1:numel (given)
      variable = given(k).global_variable;
      if (! isempty (variable))
        eval (sprintf ('global %s; %s = args{k};', variable, variable));
        keep(k) = false;
      end
    end
    args = args(keep);
    args = args(1:min (declared, numel (args)));
  elseif (declared > numel (args) && ! isempty (spec.trailing))
    args{end + 1} = spec.trailing;
  end
end

% A JSON argument as the student's function gets it: numbers JSON has none for arrive
% as strings, an empty list of lists as an empty matrix of that many rows.
function value = argument (value)
  if (ischar (value))
    switch (value)
      case 'Infinity', value = Inf;
      case '-Infinity', value = -Inf;
      case 'NaN', value = NaN;
    end
  elseif (iscell (value))
    value = cellfun (@argument, value, 'UniformOutput', false);
    if (all (cellfun (@isempty, value)))
      value = zeros (numel (value), 0);
    elseif (all (cellfun (@(v) isnumeric (v) && isscalar (v), value)))
      value = cell2mat (value);
    end
  end
end

% The most values a call may return (the JavaScript harness checks again).
function n = max_values ()
  n = 2000;
end

function text = output_text (out, spec)
  if (isempty (spec))
    text = any_text (out{1});
    return;
  end
  described = spec.outputs;
  if (numel (out) == 1)
    text = value_text (out{1}, described(1));
    return;
  end
  parts = cell (1, numel (out));
  for k = 1:numel (out)
    parts{k} = [jsonencode(described(k).name) ':' value_text(out{k}, described(k))];
  end
  text = ['{' joined(parts) '}'];
end

% One returned value in the contract's shape, as `described` says it is.
function text = value_text (value, described)
  if (isempty (described.rank) || ! (isnumeric (value) || islogical (value)))
    text = any_text (value);
    return;
  end
  if (numel (value) > max_values ())
    error ('returned an array of %d values, more than the %d a call may return', ...
           numel (value), max_values ());
  end
  rank = described.rank;
  if (described.stacked && rank == 2)
    value = value.';
  elseif (described.stacked && rank == 3)
    value = permute (value, [3 1 2]);
  end
  if (rank == 1 && ! (isvector (value) || isempty (value)))
    error ('returned a %s array, where a vector is expected', ...
           strjoin (arrayfun (@num2str, size (value), 'UniformOutput', false), ' x '));
  end
  if (described.index)
    value = value - 1;
  end
  if (described.flag && isnumeric (value))
    value = value != 0;
  end
  if (rank == 1 && ! isempty (described.headings))
    at = described.headings + 1;
    at = at(at <= numel (value));
    value(at) = mod (value(at) + pi, 2 * pi) - pi;
  end
  switch (rank)
    case 0
      text = numbers (value, '%s,');
      if (! isscalar (value))
        text = ['[' text ']'];
      end
    case 1
      text = ['[' numbers(value, '%s,') ']'];
    case 2
      text = rows_text (value);
    otherwise
      % The last index fastest: the order of the contract's nested lists.
      [~, rows, columns] = size (value);
      item = ['[' times(['[' times('%s,', columns) '],'], rows) '],'];
      text = ['[' numbers(permute (value, [3 2 1]), item) ']'];
  end
end

function text = rows_text (matrix)
  text = ['[' numbers(matrix.', ['[' times('%s,', columns (matrix)) '],']) ']'];
end

% `format` written `n` times.
function text = times (format, n)
  text = reshape (format(ones (1, n), :).', 1, []);
end

% The numbers of `value` in MATLAB's order (a column after another), printed with
% `format` over and over, `%s` standing for a number: in full precision, true and false
% for logicals, the contract's strings for numbers JSON has none for; a comma before a
% closing bracket, and at the end, dropped.
function text = numbers (value, format)
  if (iscomplex (value))
    error ('returned a complex number, where the contract has real ones');
  end
  if (isempty (value))
    text = '';
    return;
  elseif (islogical (value))
    words = {'false', 'true'};
    text = sprintf (format, words{value(:).' + 1});
  elseif (all (isfinite (value(:))))
    text = sprintf (strrep (format, '%s', '%.17g'), double (value));
  else
    text = sprintf (format, arrayfun (@number, double (value(:)).', ...
                                      'UniformOutput', false){:});
  end
  text = strrep (text, ',]', ']');
  if (text(end) == ',')
    text = text(1:end - 1);
  end
end

% One number as JSON has it, the contract's strings for those it has not.
function text = number (x)
  if (isfinite (x))
    text = sprintf ('%.17g', x);
  elseif (isnan (x))
    text = '"NaN"';
  elseif (x > 0)
    text = '"Infinity"';
  else
    text = '"-Infinity"';
  end
end

% Parts of JSON text, comma-separated.
function text = joined (parts)
  text = sprintf ('%s,', parts{:});
  text = text(1:end - 1);
end

% A value whose shape the contract leaves open (the settings `init` and `tuning` return):
% a number, a vector as a list, a matrix as rows, a struct as an object.
function text = any_text (value)
  if (isstruct (value) && isscalar (value))
    fields = fieldnames (value);
    parts = cell (1, numel (fields));
    for k = 1:numel (fields)
      parts{k} = [jsonencode(fields{k}) ':' any_text(value.(fields{k}))];
    end
    text = ['{' joined(parts) '}'];
  elseif (ischar (value))
    text = jsonencode (value);
  elseif (iscell (value))
    text = ['[' joined(cellfun (@any_text, value(:).', 'UniformOutput', false)) ']'];
  elseif ((isnumeric (value) || islogical (value)) && ndims (value) == 2)
    if (numel (value) > max_values ())
      error ('returned %d values, more than the %d a call may return', ...
             numel (value), max_values ());
    end
    if (isscalar (value))
      text = numbers (value, '%s');
    elseif (isvector (value) || isempty (value))
      text = ['[' numbers(value, '%s,') ']'];
    else
      text = rows_text (value);
    end
  else
    error ('returned a %s, which is no number, vector, matrix or struct', class (value));
  end
end

% An error in words, with the line of the student's file it came from.
function text = error_text (err, file)
  folder = student_folder ();
  message = err.message;
  line = [];
  for k = 1:numel (err.stack)
    if (strncmp (err.stack(k).file, folder, numel (folder)))
      line = student_line (err.stack(k).line, err.stack(k).file);
      break;
    end
  end
  % A parse error names the file and line in its text.
  where = regexp (message, 'near line (\d+) of file (\S+)', 'tokens', 'once');
  if (! isempty (where))
    shown = student_line (str2double (where{1}), where{2});
    message = strrep (message, [where{1} ' of file ' where{2}], ...
                      sprintf ('%d of %s', shown, file));
  end
  message = strtrim (strrep (message, [folder '/'], ''));
  if (numel (message) > 300)
    message = [message(1:300) '...'];
  end
  if (! isempty (line))
    message = sprintf ('%s (line %d)', message, line);
  end
  answer.error = ['error: ' message];
  text = jsonencode (answer);
end

% A line of the written file as a line of the student's (the script has `1;` first).
function line = student_line (line, path)
  if (! isempty (strfind (path, 'estlab_student.m')))
    line = line - 1;
  end
end
