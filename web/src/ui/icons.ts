// Toolbar icons as inline SVG (no icon font: the page must render the same with no fonts beyond
// the system's and no network).
const svg = (body: string) =>
  `<svg viewBox="0 0 16 16" width="14" height="14" fill="none" stroke="currentColor" stroke-width="1.6" stroke-linecap="round" stroke-linejoin="round" aria-hidden="true">${body}</svg>`;

export const icons = {
  zoomIn: svg('<circle cx="7" cy="7" r="4.5"/><path d="M14 14l-3.8-3.8M5 7h4M7 5v4"/>'),
  zoomOut: svg('<circle cx="7" cy="7" r="4.5"/><path d="M14 14l-3.8-3.8M5 7h4"/>'),
  fit: svg('<path d="M2 6V2h4M10 2h4v4M14 10v4h-4M6 14H2v-4"/>'),
  follow: svg('<circle cx="8" cy="8" r="2"/><circle cx="8" cy="8" r="5.5"/><path d="M8 1v2M8 13v2M1 8h2M13 8h2"/>'),
  pause: svg('<path d="M5 3v10M11 3v10" stroke-width="2.4"/>'),
  play: svg('<path d="M4 2.5v11l9-5.5z" fill="currentColor"/>'),
  link: svg('<path d="M6.5 9.5l3-3M7 4.5l1.2-1.2a2.6 2.6 0 013.7 3.7L10.7 8.2M9 11.5l-1.2 1.2a2.6 2.6 0 01-3.7-3.7L5.3 7.8"/>'),
};

export function iconElement(html: string): HTMLElement {
  const span = document.createElement('span');
  span.className = 'icon';
  span.innerHTML = html;
  return span;
}
