/* accept.h — HTTP content negotiation for /v1/render: the image format an Accept
 * header asks for, among the formats of the table (image/format.h). */
#ifndef TC_IO_ACCEPT_H
#define TC_IO_ACCEPT_H

/* The format an Accept header asks for, or -1 (no preference we can serve:
 * the caller uses its default). Only primary formats are ever chosen. */
int tc_accept_format(const char *accept);

#endif
