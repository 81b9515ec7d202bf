// The sites on the server and their map versions (GET /api/sites, /api/sites/{id}/maps), each
// version with links to its map_server files as stored. A site's versions are fetched when it is
// opened, and again on every refresh while it stays open.
import { api, currentToken, fetchBlob, siteMapFileUrl, type Site, type SiteMap } from '../net/api';
import { download, formatAge, h } from './dom';

const kRefreshMs = 10000;

export class SitesPanel {
  readonly element: HTMLElement;
  private readonly list: HTMLElement;
  private readonly state: HTMLElement;
  private readonly open = new Set<string>();
  private timer: ReturnType<typeof setTimeout> | null = null;

  constructor() {
    this.state = h('div', { class: 'list-state' });
    this.list = h('div', { class: 'site-list' });
    this.element = h('div', { class: 'sites' }, this.state, this.list);
  }

  start(): void {
    void this.refresh();
  }

  async refresh(): Promise<void> {
    if (this.timer) clearTimeout(this.timer);
    try {
      const { sites } = await api.sites();
      this.state.textContent = sites.length ? '' : 'No sites yet (POST /api/sites; sessions name theirs in settings.site).';
      this.render(sites);
    } catch (e) {
      this.state.textContent = `Sites not available: ${(e as Error).message}`;
    }
    this.timer = setTimeout(() => void this.refresh(), kRefreshMs);
  }

  private render(sites: Site[]): void {
    this.list.replaceChildren(
      ...sites.map((site) => {
        const versions = h('ul', { class: 'site-maps' });
        const row = h(
          'details',
          { class: 'site-row', 'data-site': site.id, open: this.open.has(site.id) },
          h('summary', { title: site.id }, h('span', { class: 'site-name' }, site.name || site.id), h('span', { class: 'site-meta' }, ` ${site.versions ?? 0} map${site.versions === 1 ? '' : 's'}`)),
          versions,
        );
        row.addEventListener('toggle', () => {
          if (row.open) this.open.add(site.id);
          else this.open.delete(site.id);
          if (row.open) void this.loadMaps(site.id, versions);
        });
        if (row.open) void this.loadMaps(site.id, versions);
        return row;
      }),
    );
  }

  private async loadMaps(siteId: string, host: HTMLElement): Promise<void> {
    try {
      const { maps } = await api.siteMaps(siteId);
      host.replaceChildren(...(maps.length ? maps.map((m) => this.mapRow(m)) : [h('li', { class: 'list-state' }, 'No map yet')]));
    } catch (e) {
      host.replaceChildren(h('li', { class: 'list-state' }, `Maps not available: ${(e as Error).message}`));
    }
  }

  private mapRow(m: SiteMap): HTMLElement {
    const size = m.image?.width && m.image?.height ? `${m.image.width} × ${m.image.height}` : '';
    const from = m.source === 'session' ? `from ${m.session_id ?? 'a session'}` : m.source === 'import' ? 'imported' : '';
    const meta = [from, size, m.resolution ? `${m.resolution} m/cell` : '', m.created_at ? formatAge(m.created_at) : ''].filter(Boolean).join(' · ');
    return h(
      'li',
      { class: 'site-map', 'data-version': m.version },
      h('span', { class: 'site-version' }, `v${m.version}`),
      h('span', { class: 'site-meta', title: m.note ?? '' }, meta),
      h('span', { class: 'site-files' }, this.fileLink(m, 'map.pgm'), this.fileLink(m, 'map.yaml')),
    );
  }

  // A plain link; with a viewer token, fetched with the token (a link cannot send the header).
  private fileLink(m: SiteMap, file: 'map.pgm' | 'map.yaml'): HTMLElement {
    const url = siteMapFileUrl(m.site_id, m.version, file);
    return h(
      'a',
      {
        href: url,
        download: file,
        'data-file': file,
        title: `the version's ${file === 'map.pgm' ? 'PGM' : 'YAML'} as stored`,
        onclick: (e: MouseEvent) => {
          if (!currentToken()) return;
          e.preventDefault();
          fetchBlob(url).then(
            (blob) => download(blob, file),
            (err: Error) => alert(`Download failed: ${err.message}`),
          );
        },
      },
      file,
    );
  }
}
