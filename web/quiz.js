// quiz.js: a lesson's knowledge check (the JSON of a ```check``` block) as the student answers it
// (window.quiz). Each question is rendered in order: its text, then a number input with its unit
// and tolerance (kind "numeric") or its options as radio buttons (kinds "mcq" and "predict"), a
// Check button that grades the answer, marks it right or wrong and then shows the explanation.
//
//   const question = new quiz.Question(spec, index, container);
//   question.answer(value)        // a number, or an option's index: {correct, explain}
//   quiz.richText(html)           // a DocumentFragment: the lesson's HTML, made safe, math typeset
//
// The lesson's text is HTML with TeX between $...$. It is shown as HTML, but only through a
// whitelist: the tags below become elements (without any attribute), every other tag stays
// visible as text (so "<inertial>" in a question reads as written), and no string of the lesson
// is ever assigned to innerHTML, so nothing in it can run. Math is typeset by KaTeX (Debian's
// libjs-katex, served with the page at vendor/katex/); without it, the TeX stays as written.
(function (root) {
  'use strict';

  const ALLOWED_TAGS = new Set(['p', 'br', 'code', 'pre', 'em', 'strong', 'b', 'i', 'sub', 'sup',
    'ul', 'ol', 'li']);
  const VOID_TAGS = new Set(['br']);
  const ENTITIES = {amp: '&', lt: '<', gt: '>', quot: '"', apos: "'", nbsp: '\u00a0'};
  const KINDS = ['numeric', 'mcq', 'predict'];

  function decodeEntities(text) {
    return text.replace(/&(#x[0-9a-fA-F]+|#[0-9]+|[a-zA-Z]+);/g, (whole, name) => {
      if (name[0] === '#') {
        const code = name[1] === 'x' || name[1] === 'X' ? parseInt(name.slice(2), 16) : parseInt(name.slice(1), 10);
        return code > 0 && code <= 0x10ffff ? String.fromCodePoint(code) : whole;
      }
      return Object.prototype.hasOwnProperty.call(ENTITIES, name) ? ENTITIES[name] : whole;
    });
  }

  // Text with $...$ math: text nodes and KaTeX's rendering of each formula. Inside <code> and
  // <pre>, no math.
  function appendText(parent, text, math) {
    if (!math || typeof root.katex === 'undefined') {
      parent.appendChild(document.createTextNode(text));
      return;
    }
    const pattern = /\$([^$]+)\$/g;
    let last = 0;
    let match;
    while ((match = pattern.exec(text)) !== null) {
      if (match.index > last) parent.appendChild(document.createTextNode(text.slice(last, match.index)));
      const span = document.createElement('span');
      span.className = 'math';
      // trust: false (KaTeX's default) keeps \href, \url and \htmlId from making links or ids
      root.katex.render(match[1], span, {throwOnError: false, trust: false});
      parent.appendChild(span);
      last = pattern.lastIndex;
    }
    if (last < text.length) parent.appendChild(document.createTextNode(text.slice(last)));
  }

  /** The lesson's HTML as a safe DocumentFragment (see the top of this file). */
  function richText(html) {
    const source = String(html);
    const fragment = document.createDocumentFragment();
    const stack = [fragment];
    const names = [];
    const inCode = () => names.includes('code') || names.includes('pre');
    const tag = /<(\/?)([a-zA-Z][a-zA-Z0-9-]*)([^<>]*)>/g;
    let last = 0;
    let match;
    const text = (s) => {
      if (s) appendText(stack[stack.length - 1], decodeEntities(s), !inCode());
    };
    while ((match = tag.exec(source)) !== null) {
      text(source.slice(last, match.index));
      last = tag.lastIndex;
      const closing = match[1] === '/';
      const name = match[2].toLowerCase();
      if (!ALLOWED_TAGS.has(name)) {
        text(match[0].replace(/&/g, '&amp;'));  // shown as written
        continue;
      }
      if (closing) {
        const depth = names.lastIndexOf(name);
        if (depth >= 0) {  // close it and whatever was left open inside it
          names.length = depth;
          stack.length = depth + 1;
        }
        continue;
      }
      const e = document.createElement(name);  // attributes, events included, are dropped
      stack[stack.length - 1].appendChild(e);
      if (!VOID_TAGS.has(name)) {
        stack.push(e);
        names.push(name);
      }
    }
    text(source.slice(last));
    return fragment;
  }

  function element(tag, attributes, text) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attributes || {})) e.setAttribute(k, v);
    if (text !== undefined) e.textContent = text;
    return e;
  }

  /** A question of the spec that cannot be asked: `where` names it. */
  class QuizError extends Error {
    constructor(message) {
      super(message);
      this.name = 'QuizError';
    }
  }

  class Question {
    constructor(spec, index, container) {
      this.spec = spec;
      this.index = index;
      const where = 'question ' + (index + 1);
      if (!spec || typeof spec !== 'object') throw new QuizError(where + ' is not an object');
      if (!KINDS.includes(spec.kind)) {
        throw new QuizError(where + ' has kind ' + JSON.stringify(spec.kind) + ' (numeric, mcq or predict)');
      }
      if (typeof spec.q !== 'string') throw new QuizError(where + ' has no text "q"');
      if (spec.kind === 'numeric') {
        if (!Number.isFinite(spec.answer) || !(spec.tol >= 0)) {
          throw new QuizError(where + ' (numeric) needs a number "answer" and a tolerance "tol" >= 0');
        }
      } else if (!Array.isArray(spec.options) || spec.options.length < 2 ||
          !Number.isInteger(spec.answer) || spec.answer < 0 || spec.answer >= spec.options.length) {
        throw new QuizError(where + ' (' + spec.kind + ') needs "options" and "answer", the index of one');
      }
      this.build(container);
    }

    build(container) {
      const s = this.spec;
      const root_ = element('section', {class: 'question-block', 'data-kind': s.kind,
        'data-question': String(this.index)});
      const heading = element('h3', {}, 'Question ' + (this.index + 1) +
        (s.kind === 'predict' ? ': predict, then measure' : ''));
      const prompt = element('div', {class: 'prompt'});
      prompt.appendChild(richText(s.q));
      root_.append(heading, prompt);
      const form = element('div', {class: 'answer'});
      if (s.kind === 'numeric') {
        this.input = element('input', {type: 'text', inputmode: 'decimal', class: 'numeric',
          'aria-label': 'your answer' + (s.unit ? ' in ' + s.unit : '')});
        const unit = element('span', {class: 'unit'}, s.unit || '');
        const tolerance = element('span', {class: 'tolerance muted'},
          'graded to \u00b1' + s.tol + (s.unit ? ' ' + s.unit : ''));
        this.input.addEventListener('keydown', (event) => {
          if (event.key === 'Enter') this.checkFromPage();
        });
        form.append(this.input, ' ', unit, ' ', tolerance);
      } else {
        this.choices = s.options.map((option, i) => {
          const label = element('label', {class: 'option'});
          const radio = element('input', {type: 'radio', name: 'question-' + this.index, value: String(i)});
          const text = element('span');
          text.appendChild(richText(option));
          label.append(radio, ' ', text);
          form.appendChild(label);
          return radio;
        });
      }
      const row = element('div', {class: 'check-row'});
      this.button = element('button', {type: 'button', class: 'check'}, 'Check');
      this.button.addEventListener('click', () => this.checkFromPage());
      this.verdict = element('span', {class: 'verdict', role: 'status'});
      row.append(this.button, ' ', this.verdict);
      this.explanation = element('div', {class: 'explain'});
      this.explanation.appendChild(richText(s.explain || ''));
      this.explanation.hidden = true;
      root_.append(form, row, this.explanation);
      container.appendChild(root_);
      this.root = root_;
    }

    // the Check button: read what the page holds, grade it (or say what is missing)
    checkFromPage() {
      if (this.spec.kind === 'numeric') {
        const text = this.input.value.trim().replace(',', '.');
        const value = text === '' ? NaN : Number(text);
        if (!Number.isFinite(value)) {
          this.say('Enter a number' + (this.spec.unit ? ' in ' + this.spec.unit : '') + '.', '');
          return null;
        }
        return this.grade(value);
      }
      const chosen = this.choices.findIndex((radio) => radio.checked);
      if (chosen < 0) {
        this.say('Choose an option.', '');
        return null;
      }
      return this.grade(chosen);
    }

    /** What the student's input and click do: puts `value` on the page, then grades it. */
    answer(value) {
      if (this.spec.kind === 'numeric') {
        if (typeof value !== 'number' || !Number.isFinite(value)) {
          throw new QuizError('question ' + (this.index + 1) + ' wants a number, not ' + JSON.stringify(value));
        }
        this.input.value = String(value);
      } else {
        if (!Number.isInteger(value) || value < 0 || value >= this.choices.length) {
          throw new QuizError('question ' + (this.index + 1) + ' has options 0..' +
            (this.choices.length - 1) + ', not ' + JSON.stringify(value));
        }
        this.choices[value].checked = true;
      }
      return this.checkFromPage();
    }

    grade(value) {
      const s = this.spec;
      const correct = s.kind === 'numeric' ? Math.abs(value - s.answer) <= s.tol : value === s.answer;
      this.say(correct ? 'Right.' : 'Not quite.', correct ? 'right' : 'wrong');
      this.explanation.hidden = false;
      return {correct, explain: s.explain || ''};
    }

    say(text, state) {
      this.verdict.textContent = text;
      this.root.classList.toggle('right', state === 'right');
      this.root.classList.toggle('wrong', state === 'wrong');
    }

    /** What a script may know of the question: not its answer. */
    describe() {
      const s = this.spec;
      const d = {index: this.index, kind: s.kind, q: s.q};
      if (s.kind === 'numeric') Object.assign(d, {unit: s.unit || '', tol: s.tol});
      else d.options = s.options.slice();
      return d;
    }
  }

  root.quiz = {Question, QuizError, richText};
})(window);
