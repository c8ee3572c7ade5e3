// ESLint for the scripts of softbench's pages (report/*.js), run by the lint
// preset (CMakePresets.json) in CI: ESLint's recommended rules.
'use strict';
const js = require('@eslint/js');

const browser = {
  document: 'readonly', window: 'readonly', location: 'readonly',
  Image: 'readonly', Event: 'readonly',
};
const node = {
  require: 'readonly', module: 'writable', process: 'readonly',
  console: 'readonly', __dirname: 'readonly',
};

module.exports = [
  {ignores: ['node_modules/**']},
  js.configs.recommended,
  {
    files: ['tune_page.js'],
    languageOptions: {sourceType: 'script', globals: browser},
  },
  {
    files: ['tune_core.js'],
    languageOptions: {sourceType: 'script', globals: {module: 'writable'}},
  },
  {
    files: ['check_tune_core.js', 'eslint.config.js'],
    languageOptions: {sourceType: 'commonjs', globals: node},
  },
];
